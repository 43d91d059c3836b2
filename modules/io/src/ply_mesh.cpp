// Our own PLY mesh reader and writer. Assimp's PLY importer drops per-face properties,
// and PCL's PolygonMesh would cost a copy through PCLPointCloud2; this one streams the
// file once and keeps the face `label`.

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <limits>
#include <vector>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>
#include <plantnbv/io/mesh_io.h>

#include "io_util.h"
#include "ply_format.h"
#include "polygon_triangulation.h"

namespace plantnbv {
namespace io {

namespace {

using detail::isInteger;
using detail::PlyBody;
using detail::PlyElement;
using detail::PlyFormat;
using detail::PlyHeader;
using detail::PlyProperty;
using detail::PlyType;
using detail::sizeOf;

int findProperty(const PlyElement& e, const char* name)
{
  for (std::size_t i = 0; i < e.properties.size(); ++i)
    if (e.properties[i].name == name)
      return static_cast<int>(i);
  return -1;
}

constexpr std::uint32_t kMaxPartLabel = static_cast<std::uint32_t>(kLastPartLabel);

/// The faces of more than 3 corners, read as fans and cut properly once the vertices are
/// known (the face element may come first): face f's corners are
/// corners[begin[f]..begin[f + 1]), its n - 2 triangles start at first_triangle[f].
struct Polygons {
  std::vector<std::uint64_t> face, first_triangle, begin{0};
  std::vector<std::uint32_t> corners;
};

void readVertices(const std::string& path, const PlyElement& e, PlyBody& body,
                  TriangleMesh& mesh)
{
  int xyz[3];
  const char* const kAxes[] = {"x", "y", "z"};
  for (int a = 0; a < 3; ++a) {
    xyz[a] = findProperty(e, kAxes[a]);
    if (xyz[a] < 0 || e.properties[xyz[a]].is_list)
      throw FormatError(detail::where(path) + "the vertex element has no scalar '" +
                        kAxes[a] + "' property");
  }
  if (!mesh.vertices.empty())
    throw FormatError(detail::where(path) + "more than one vertex element");
  if (e.count > std::numeric_limits<std::uint32_t>::max())
    throw FormatError(detail::where(path) + std::to_string(e.count) +
                      " vertices exceed the 2^32 - 1 a mesh can index");
  mesh.vertices.resize(static_cast<std::size_t>(e.count));
  for (auto& v : mesh.vertices)
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const auto& p = e.properties[i];
      const int axis = static_cast<int>(i) == xyz[0]   ? 0
                       : static_cast<int>(i) == xyz[1] ? 1
                       : static_cast<int>(i) == xyz[2] ? 2
                                                       : -1;
      if (axis < 0)
        body.skip(p, "vertex data");
      else
        v[axis] = static_cast<float>(body.read(p.type, "vertex data"));
    }
}

void readFaces(const std::string& path, const PlyElement& e, PlyBody& body,
               const InputLimits& limits, TriangleMesh& mesh, Polygons& polygons)
{
  int indices = findProperty(e, "vertex_indices");
  if (indices < 0)
    indices = findProperty(e, "vertex_index");
  if (indices < 0 || !e.properties[indices].is_list ||
      !isInteger(e.properties[indices].type))
    throw FormatError(detail::where(path) +
                      "the face element has no integer list 'vertex_indices' or "
                      "'vertex_index'");
  const int label = findProperty(e, "label");
  if (label >= 0 && (e.properties[label].is_list || !isInteger(e.properties[label].type)))
    throw FormatError(detail::where(path) +
                      "the face property 'label' must be one integer");
  if (!mesh.triangles.empty())
    throw FormatError(detail::where(path) + "more than one face element");
  // Most faces are triangles; the reservation is bounded by the file size (checked by the
  // caller) and by max_triangles.
  const std::uint64_t max_triangles = limits.max_triangles;
  std::uint64_t reserve = e.count;
  if (max_triangles > 0)
    reserve = std::min(reserve, max_triangles + 1);
  mesh.triangles.reserve(static_cast<std::size_t>(reserve));
  if (label >= 0)
    mesh.labels.reserve(static_cast<std::size_t>(reserve));
  for (std::uint64_t f = 0; f < e.count; ++f) {
    std::uint32_t face_label = 0;
    for (std::size_t i = 0; i < e.properties.size(); ++i) {
      const auto& p = e.properties[i];
      if (static_cast<int>(i) == label) {
        const double l = body.read(p.type, "face data");
        if (l < 0 || l > kMaxPartLabel)
          throw FormatError(detail::where(path) + "face " + std::to_string(f) +
                            ": label " + shortestText(l) +
                            " is not a part label (expected 0.." +
                            std::to_string(kMaxPartLabel) + ")");
        face_label = static_cast<std::uint32_t>(l);
      } else if (static_cast<int>(i) != indices)
        body.skip(p, "face data");
      else {
        // A fan around the first vertex for now (Polygons); faces with fewer than 3
        // vertices add nothing.
        const std::uint64_t n = body.readCount(p.count_type, "face data");
        if (n > 3) {
          polygons.face.push_back(f);
          polygons.first_triangle.push_back(mesh.triangles.size());
        }
        std::uint32_t first = 0, previous = 0;
        for (std::uint64_t k = 0; k < n; ++k) {
          const double idx = body.read(p.type, "face data");
          if (idx < 0 || idx > std::numeric_limits<std::uint32_t>::max())
            throw FormatError(detail::where(path) + "face " + std::to_string(f) +
                              ": invalid vertex index " + shortestText(idx));
          const auto current = static_cast<std::uint32_t>(idx);
          if (n > 3)
            polygons.corners.push_back(current);
          if (k == 0)
            first = current;
          else if (k >= 2) {
            if (max_triangles > 0 && mesh.triangles.size() >= max_triangles)
              throw FormatError(detail::where(path) + "more than " +
                                std::to_string(max_triangles) +
                                " triangles (the limit, InputLimits::max_triangles)");
            mesh.triangles.push_back({first, previous, current});
          }
          previous = current;
        }
        if (n > 3)
          polygons.begin.push_back(polygons.corners.size());
      }
    }
    if (label >= 0)
      mesh.labels.resize(mesh.triangles.size(), static_cast<PartLabel>(face_label));
  }
}

/// Little-endian serialisation into a buffer flushed to the file in large blocks.
class LittleEndianWriter {
public:
  explicit LittleEndianWriter(std::ostream& out) : out_(out) { buffer_.reserve(kBlock); }
  ~LittleEndianWriter() { flush(); }

  void u8(std::uint8_t v) { put(&v, 1); }
  void u32(std::uint32_t v)
  {
    const std::uint8_t b[4] = {
        static_cast<std::uint8_t>(v), static_cast<std::uint8_t>(v >> 8),
        static_cast<std::uint8_t>(v >> 16), static_cast<std::uint8_t>(v >> 24)};
    put(b, 4);
  }
  void f32(float v)
  {
    std::uint32_t bits;
    std::memcpy(&bits, &v, 4);
    u32(bits);
  }
  void flush()
  {
    out_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

private:
  static constexpr std::size_t kBlock = 1 << 20;
  void put(const void* p, std::size_t n)
  {
    const char* c = static_cast<const char*>(p);
    buffer_.insert(buffer_.end(), c, c + n);
    if (buffer_.size() >= kBlock)
      flush();
  }
  std::ostream& out_;
  std::vector<char> buffer_;
};

} // namespace

namespace detail {

TriangleMesh readPlyMesh(const std::string& path, const InputLimits& limits)
{
  requireRegularFile(path);
  checkFileSize(path, limits);
  std::ifstream in(path, std::ios::binary);
  const PlyHeader header = readPlyHeader(path, in);
  // Refuse counts over the limits or that the file cannot hold before anything is
  // allocated for them.
  if (const PlyElement* vertex = findElement(header, "vertex"))
    checkLimit(path, vertex->count, "vertices", limits.max_points, "max_points");
  checkPlyBodySize(path, in, header);
  PlyBody body(path, in, header.format);
  TriangleMesh mesh;
  Polygons polygons;
  bool have_vertices = false;
  for (const auto& e : header.elements) {
    if (e.name == "vertex") {
      readVertices(path, e, body, mesh);
      have_vertices = true;
    } else if (e.name == "face")
      readFaces(path, e, body, limits, mesh, polygons);
    else
      for (std::uint64_t i = 0; i < e.count; ++i)
        for (const auto& p : e.properties)
          body.skip(p, "element data");
  }
  if (!have_vertices)
    throw FormatError(where(path) + "no vertex element");
  // The polygons' fans replaced by triangles of their true area (a fan overlaps itself
  // on a polygon that is not convex). One with a bad index is left to mesh.validate().
  std::vector<std::uint32_t> corners;
  std::vector<std::array<std::uint32_t, 3>> cut;
  std::uint64_t steps_left = kEarClippingStepsPerFile;
  for (std::size_t k = 0; k < polygons.face.size(); ++k) {
    corners.assign(polygons.corners.begin() + polygons.begin[k],
                   polygons.corners.begin() + polygons.begin[k + 1]);
    if (std::any_of(corners.begin(), corners.end(),
                    [&](std::uint32_t c) { return c >= mesh.vertices.size(); }))
      continue;
    cut.clear();
    const PolygonCut done = triangulatePolygon(mesh.vertices, corners, cut, steps_left);
    if (done != PolygonCut::cut)
      throw FormatError(where(path) + "face " + std::to_string(polygons.face[k]) + ": " +
                        untriangulableFace(done, corners.size()));
    std::copy(cut.begin(), cut.end(),
              mesh.triangles.begin() +
                  static_cast<std::ptrdiff_t>(polygons.first_triangle[k]));
  }
  return mesh;
}

} // namespace detail

void saveMeshPly(const std::string& path, const TriangleMesh& mesh)
{
  try {
    mesh.validate();
  } catch (const FormatError& e) {
    throw FormatError(detail::where(path) +
                      "refusing to write an invalid mesh: " + e.what());
  }
  AtomicFile file(path); // a failed write leaves the previous file whole
  std::ostream& out = file.stream();
  out << "ply\n"
      << "format binary_little_endian 1.0\n"
      << "comment written by plantnbv\n"
      << "element vertex " << mesh.vertices.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "element face " << mesh.triangles.size() << "\n"
      << "property list uchar uint vertex_indices\n";
  if (mesh.hasLabels())
    out << "property uint label\n";
  out << "end_header\n";
  {
    LittleEndianWriter w(out);
    for (const auto& v : mesh.vertices) {
      w.f32(v.x());
      w.f32(v.y());
      w.f32(v.z());
    }
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      w.u8(3);
      for (auto i : mesh.triangles[t])
        w.u32(i);
      if (mesh.hasLabels())
        w.u32(static_cast<std::uint32_t>(mesh.labels[t]));
    }
  }
  file.commit();
}

} // namespace io
} // namespace plantnbv
