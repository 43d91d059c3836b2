#include "polygon_triangulation.h"

#include <algorithm>
#include <cmath>

namespace plantnbv {
namespace io {
namespace detail {

namespace {

struct Point2 {
  double x, y;
};

bool same(const Point2& a, const Point2& b)
{
  return a.x == b.x && a.y == b.y;
}

/// Twice the signed area of the triangle abc (> 0: counter-clockwise).
double cross(const Point2& a, const Point2& b, const Point2& c)
{
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

} // namespace

PolygonCut triangulatePolygon(const std::vector<Eigen::Vector3f>& vertices,
                              const std::vector<std::uint32_t>& corners,
                              std::vector<std::array<std::uint32_t, 3>>& triangles,
                              std::uint64_t& steps_left)
{
  const std::size_t n = corners.size();
  if (n < 3)
    return PolygonCut::cut;
  if (n == 3) {
    triangles.push_back({corners[0], corners[1], corners[2]});
    return PolygonCut::cut;
  }
  // Newell's normal: its length is twice the area of a planar simple polygon, whatever
  // the polygon's shape; the plane drops its largest axis.
  Eigen::Vector3d normal = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d a = vertices[corners[i]].cast<double>();
    const Eigen::Vector3d b = vertices[corners[(i + 1) % n]].cast<double>();
    normal += Eigen::Vector3d((a.y() - b.y()) * (a.z() + b.z()),
                              (a.z() - b.z()) * (a.x() + b.x()),
                              (a.x() - b.x()) * (a.y() + b.y()));
  }
  int drop = 0;
  normal.cwiseAbs().maxCoeff(&drop);
  const int u = (drop + 1) % 3, v = (drop + 2) % 3;
  // Counter-clockwise in (u, v) when the normal points along +drop.
  const double sign = normal[drop] < 0.0 ? -1.0 : 1.0;
  std::vector<Point2> p(n);
  double scale = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3f& q = vertices[corners[i]];
    p[i] = {double(q[u]), sign * double(q[v])};
    scale = std::max({scale, std::abs(p[i].x), std::abs(p[i].y)});
  }
  // Turns below this count as straight: float corners (rounded to 6e-8 of their
  // magnitude) on a line, moved into a plane, turn by up to about 1e-7 scale^2; such a
  // corner is cut off as a triangle of area at most 5e-7 scale^2.
  const double eps = 1e-6 * scale * scale;

  std::vector<std::size_t> prev(n), next(n);
  for (std::size_t i = 0; i < n; ++i) {
    prev[i] = (i + n - 1) % n;
    next[i] = (i + 1) % n;
  }
  auto turn = [&](std::size_t i) { return cross(p[prev[i]], p[i], p[next[i]]); };
  // A straight corner: a turn within eps, or (exactly, whatever the rounding) a repeated
  // corner or the tip of a spike that returns to where it left.
  auto straight = [&](std::size_t i) {
    return std::abs(turn(i)) <= eps || same(p[prev[i]], p[next[i]]) ||
           same(p[prev[i]], p[i]) || same(p[i], p[next[i]]);
  };
  // Convex: every corner turns left or goes straight on (not back: a spike), and the
  // turns add up to one full turn (not a pentagram's two); repeated corners aside.
  bool convex = true;
  double turning = 0.0;
  for (std::size_t i = 0; i < n && convex; ++i) {
    const std::size_t j = (i + 1) % n;
    if (same(p[i], p[j]))
      continue;
    std::size_t k = (j + 1) % n;
    while (same(p[j], p[k]) && k != i)
      k = (k + 1) % n;
    const double t = cross(p[i], p[j], p[k]);
    const double dot =
        (p[j].x - p[i].x) * (p[k].x - p[j].x) + (p[j].y - p[i].y) * (p[k].y - p[j].y);
    convex = t > eps || (t >= -eps && dot > 0.0);
    turning += std::atan2(t, dot);
  }
  convex = convex && std::abs(turning - 2.0 * M_PI) < 1e-6;
  if (convex) {
    for (std::size_t i = 1; i + 1 < n; ++i)
      triangles.push_back({corners[0], corners[i], corners[i + 1]});
    return PolygonCut::cut;
  }

  std::vector<std::array<std::uint32_t, 3>> cut;
  cut.reserve(n - 2);
  auto clip = [&](std::size_t i) {
    cut.push_back({corners[prev[i]], corners[i], corners[next[i]]});
    next[prev[i]] = next[i];
    prev[next[i]] = prev[i];
  };
  // An ear: a convex corner whose triangle holds no other corner that is not convex
  // (inside or on its edges; corners at the same place as its own do not count).
  bool over_budget = false;
  auto isEar = [&](std::size_t i) {
    const Point2 &a = p[prev[i]], &b = p[i], &c = p[next[i]];
    for (std::size_t j = next[next[i]]; j != prev[i]; j = next[j]) {
      if (steps_left == 0) {
        over_budget = true;
        return false;
      }
      --steps_left;
      if (turn(j) > eps)
        continue;
      const Point2& q = p[j];
      if (same(q, a) || same(q, b) || same(q, c))
        continue;
      if (cross(a, b, q) >= -eps && cross(b, c, q) >= -eps && cross(c, a, q) >= -eps)
        return false;
    }
    return true;
  };
  std::size_t remaining = n;
  // Straight corners go first, and the neighbours of every cut corner are cut too when
  // they become straight, so that no ear is tested against a fold of zero width.
  std::vector<std::size_t> todo;
  auto cutStraight = [&] {
    while (!todo.empty() && remaining > 3) {
      const std::size_t j = todo.back();
      todo.pop_back();
      if (prev[next[j]] != j || !straight(j)) // already cut, or not straight
        continue;
      todo.push_back(prev[j]);
      todo.push_back(next[j]);
      clip(j);
      --remaining;
    }
    todo.clear();
  };
  for (std::size_t j = 0; j < n; ++j)
    todo.push_back(n - 1 - j);
  cutStraight();
  std::size_t i = 0, tried = 0;
  while (prev[next[i]] != i) // i was cut
    ++i;
  while (remaining > 3) {
    const bool ear = turn(i) > eps && isEar(i);
    if (over_budget)
      return PolygonCut::over_budget;
    if (ear) {
      const std::size_t back = prev[i];
      clip(i);
      --remaining;
      todo = {back, next[back]};
      cutStraight();
      i = back;
      while (prev[next[i]] != i) // cut as straight: go on from a live corner
        i = next[i];
      tried = 0;
      continue;
    }
    if (++tried > remaining)
      return PolygonCut::crosses_itself; // no ear
    i = next[i];
  }
  cut.push_back({corners[prev[i]], corners[i], corners[next[i]]});
  triangles.insert(triangles.end(), cut.begin(), cut.end());
  return PolygonCut::cut;
}

std::string untriangulableFace(PolygonCut why, std::size_t corners)
{
  const std::string face = "a face of " + std::to_string(corners) + " corners";
  if (why == PolygonCut::over_budget)
    return face + " is not convex and takes the file over " +
           std::to_string(kEarClippingStepsPerFile) +
           " steps of ear clipping (the limit of one file's non-convex faces)";
  return face + " crosses itself; its area is undefined";
}

} // namespace detail
} // namespace io
} // namespace plantnbv
