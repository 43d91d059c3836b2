#include <algorithm>
#include <cmath>
#include <sstream>

#include <Eigen/Geometry>

#include <plantnbv/common/error.h>
#include <plantnbv/common/random.h>
#include <plantnbv/common/portable_math.h>
#include <plantnbv/plant/tomato_plant_generator.h>

#include "mesh_builder.h"

namespace plantnbv {

using plant_detail::Cap;
using plant_detail::MeshBuilder;
using Vec3 = Eigen::Vector3d;

namespace {

constexpr double kDeg = M_PI / 180.0;

// Botanical limits (docs/plants.md gives the sources). Every drawn value is clamped to
// them, so no seed can leave the documented ranges.
constexpr double kStemHeightMin = 0.45, kStemHeightMax = 0.70;
constexpr double kStemRadiusMin = 0.0025, kStemRadiusMax = 0.0045;
constexpr double kLeafLengthMin = 0.15, kLeafLengthMax = 0.40;
constexpr double kLeafletLengthMin = 0.03, kLeafletLengthMax = 0.09;
constexpr double kLeafletWidthMin = 0.02, kLeafletWidthMax = 0.04;
constexpr double kFruitRadiusMin = 0.012, kFruitRadiusMax = 0.030;
constexpr int kFruitsMin = 2, kFruitsMax = 6;
/// Lowest point any leaf may reach above the base (the pot's rim).
constexpr double kMinPartHeight = 0.01;

// Independent random streams, so that the draws of one part never depend on how many
// draws another part made.
constexpr std::uint64_t kPlantStream = 0, kLeafStream = 1000, kTrussStream = 2000;

double lerp(double a, double b, double t)
{
  return a + (b - a) * t;
}
double clamp(double x, double lo, double hi)
{
  return std::min(std::max(x, lo), hi);
}

/// The draws of one stream, scaled by the config's variation. Every call consumes
/// exactly one number, whatever the variation, so streams stay aligned.
class Draws {
public:
  Draws(std::uint64_t seed, std::uint64_t stream, double variation)
      : rng_(deriveSeed(seed, stream)), variation_(variation)
  {
  }
  /// Uniform in [-a, a] times the variation.
  double jitter(double a) { return variation_ * rng_.uniform(-a, a); }
  /// 1 + jitter(rel): a relative deviation.
  double factor(double rel) { return 1.0 + jitter(rel); }
  /// Uniform in [0, 1) when variation is 1, 0.5 when it is 0.
  double unit() { return 0.5 + jitter(0.5); }

private:
  Rng rng_;
  double variation_;
};

Vec3 horizontal(double azimuth_rad)
{
  double s, c;
  portableSinCos(azimuth_rad, s, c);
  return Vec3(c, s, 0.0);
}

/// Angular distance in [0, pi].
double angularDistance(double a, double b)
{
  double d = std::fmod(std::abs(a - b), 2.0 * M_PI);
  return std::min(d, 2.0 * M_PI - d);
}

int scaled(int base, double detail, int minimum)
{
  return std::max(minimum, static_cast<int>(std::lround(base * detail)));
}

// ---------------------------------------------------------------------------------
// Stem: a centre line c(z) = (offset(z), z) bending slightly, radius tapering from the
// base with a small swelling at each node.

struct StemShape {
  double height = 0.0; // apex tip above the base
  double r_base = 0.0, r_top = 0.0;
  Vec3 bend_dir{Vec3::UnitX()}, wave_dir{Vec3::UnitY()};
  double bend_m = 0.0, wave_m = 0.0, wave_freq = 0.0, wave_phase = 0.0;
  std::vector<double> node_z;

  Vec3 center(double z) const
  {
    const double u = z / height;
    const double wave = portableSin(wave_freq * u + wave_phase) - portableSin(wave_phase);
    return bend_m * u * u * bend_dir + wave_m * wave * wave_dir + Vec3(0, 0, z);
  }
  double radius(double z) const
  {
    double r = lerp(r_base, r_top, clamp(z / height, 0.0, 1.0));
    for (double zn : node_z) {
      const double d = (z - zn) / 0.008;
      if (std::abs(d) < 1.0)
        r *= 1.0 + 0.08 * (1.0 - d * d) * (1.0 - d * d);
    }
    return std::min(r, kStemRadiusMax);
  }
};

// ---------------------------------------------------------------------------------
// A curved organ axis (petiole + rachis, peduncle): starts inside the stem, leaves it at
// arc length `s_junction`, then bends in elevation (theta) and azimuth (psi) with the
// fraction u of its free length.

struct OrganAxis {
  double theta0 = 0.0;        // elevation at the stem (rad, up positive)
  double droop = 0.0;         // total loss of elevation along the free length (rad)
  double droop_linear = 0.35; // share of the droop linear in u (rest quadratic)
  double psi0 = 0.0;          // azimuth at the stem
  double swing = 0.0;         // change of azimuth along the free length
  double s_junction = 0.0, length = 0.0; // free length from the stem surface
  double ds = 0.0;
  std::vector<Vec3> points; // uniform in arc length, points[0] inside the stem

  double u(double s) const { return clamp((s - s_junction) / length, 0.0, 1.0); }
  Vec3 direction(double s) const
  {
    const double t = u(s);
    const double theta =
        theta0 - droop * (droop_linear * t + (1.0 - droop_linear) * t * t);
    double st, ct;
    portableSinCos(theta, st, ct);
    return ct * horizontal(psi0 + swing * t) + st * Vec3::UnitZ();
  }
  void build(const Vec3& start, double step)
  {
    const double total = s_junction + length;
    const int n = std::max(8, static_cast<int>(std::ceil(total / step)));
    ds = total / n;
    points.assign(1, start);
    for (int i = 0; i < n; ++i)
      points.push_back(points.back() + ds * direction((i + 0.5) * ds));
  }
  Vec3 at(double s) const
  {
    const double x = clamp(s / ds, 0.0, static_cast<double>(points.size() - 1));
    const auto i = std::min(static_cast<std::size_t>(x), points.size() - 2);
    const double f = x - static_cast<double>(i);
    return (1.0 - f) * points[i] + f * points[i + 1];
  }
  double end() const { return s_junction + length; }
};

// ---------------------------------------------------------------------------------
// A leaflet blade over (u, v) in [0, 1] x [-1, 1]: u along the midrib, v across.

struct LeafletShape {
  Vec3 base, d, e, n; // midrib direction d, across e, normal n (towards the upper side)
  double length = 0.0, width = 0.0;
  double bend = 0.0;  // drop of the tip along -n, as a fraction of the length
  double cup = 0.0;   // rise of the margins along n, as a fraction of the half width
  double twist = 0.0; // rotation of the blade about the midrib at the tip (rad)
  double teeth = 0.0, teeth_phase = 0.0;
  bool terminal = false;

  /// Half width: ovate, widest a third of the way, rounded base and acute tip, with
  /// a saw-toothed (serrate) margin.
  double halfWidth(double u) const
  {
    const double ovate = 2.598076211353316 * std::sqrt(u) * (1.0 - u); // max 1 at u = 1/3
    const double x = u * teeth + teeth_phase;
    const double serration = 1.0 - 0.07 * (x - std::floor(x));
    return 0.5 * width * ovate * serration;
  }
  Vec3 point(double u, double v, double twist_sin, double twist_cos) const
  {
    const double half = halfWidth(u);
    const double y = half * v;
    const double z = -bend * length * u * u + cup * (y * y) / (0.5 * width);
    const Vec3 e_t = twist_cos * e + twist_sin * n;
    const Vec3 n_t = twist_cos * n - twist_sin * e;
    return base + length * u * d + y * e_t + z * n_t;
  }
};

void addLeaflet(MeshBuilder& mb, const LeafletShape& b, int rows, int columns)
{
  // Fans at the base and the tip, where the width is zero: no degenerate triangles.
  double ts, tc;
  const std::uint32_t base = mb.vertex(b.point(0.0, 0.0, 0.0, 1.0));
  std::uint32_t first = 0;
  for (int i = 1; i < rows; ++i) {
    const double u = static_cast<double>(i) / rows;
    portableSinCos(b.twist * u, ts, tc);
    for (int j = 0; j <= columns; ++j) {
      const std::uint32_t id = mb.vertex(b.point(u, 2.0 * j / columns - 1.0, ts, tc));
      if (i == 1 && j == 0)
        first = id;
    }
  }
  portableSinCos(b.twist, ts, tc);
  const std::uint32_t tip = mb.vertex(b.point(1.0, 0.0, ts, tc));
  const auto cols = static_cast<std::uint32_t>(columns);
  const std::uint32_t row = cols + 1;
  // Winding: (along u) x (along v) = d x e = n, so every triangle faces +n.
  for (std::uint32_t j = 0; j < cols; ++j)
    mb.triangle(base, first + j, first + j + 1);
  for (std::uint32_t i = 0; i + 2 < static_cast<std::uint32_t>(rows); ++i)
    for (std::uint32_t j = 0; j < cols; ++j) {
      const std::uint32_t a = first + i * row + j;
      mb.triangle(a, a + row, a + 1);
      mb.triangle(a + 1, a + row, a + row + 1);
    }
  const std::uint32_t last = first + static_cast<std::uint32_t>(rows - 2) * row;
  for (std::uint32_t j = 0; j < cols; ++j)
    mb.triangle(tip, last + j + 1, last + j);
}

std::string twoDigits(int i)
{
  return (i < 10 ? "0" : "") + std::to_string(i);
}

void checkRange(const char* name, double value, double lo, double hi,
                bool lo_open = false)
{
  const bool ok =
      std::isfinite(value) && (lo_open ? value > lo : value >= lo) && value <= hi;
  if (!ok) {
    std::ostringstream s;
    s << "TomatoPlantGenerator: " << name << " " << value << " is outside "
      << (lo_open ? "(" : "[") << lo << ", " << hi << "]";
    throw InvalidArgumentError(s.str());
  }
}

} // namespace

// -----------------------------------------------------------------------------------
// Config and setters

std::string TomatoPlantGenerator::Config::toString() const
{
  std::ostringstream s;
  s << "seed: " << seed << "\ngrowth_stage: " << growth_stage
    << "\nvariation: " << variation
    << "\ndivergence_angle_deg: " << divergence_angle_rad / kDeg
    << "\nsimplified: " << (simplified ? "true" : "false")
    << "\nmesh_detail: " << mesh_detail << "\n";
  return s.str();
}

TomatoPlantGenerator::TomatoPlantGenerator(const Config& config)
{
  setConfig(config);
}

void TomatoPlantGenerator::setConfig(const Config& config)
{
  // Check everything before assigning anything: no half-applied config.
  checkRange("growth_stage", config.growth_stage, 0.0, 1.0);
  checkRange("variation", config.variation, 0.0, 1.0);
  checkRange("divergence_angle_rad", config.divergence_angle_rad, 0.0, M_PI, true);
  checkRange("mesh_detail", config.mesh_detail, 0.25, 4.0);
  config_ = config;
}

void TomatoPlantGenerator::setGrowthStage(double stage)
{
  checkRange("growth_stage", stage, 0.0, 1.0);
  config_.growth_stage = stage;
}

void TomatoPlantGenerator::setVariation(double variation)
{
  checkRange("variation", variation, 0.0, 1.0);
  config_.variation = variation;
}

void TomatoPlantGenerator::setDivergenceAngle(double angle_rad)
{
  checkRange("divergence_angle_rad", angle_rad, 0.0, M_PI, true);
  config_.divergence_angle_rad = angle_rad;
}

void TomatoPlantGenerator::setMeshDetail(double detail)
{
  checkRange("mesh_detail", detail, 0.25, 4.0);
  config_.mesh_detail = detail;
}

TomatoPlantGenerator::Config defaultPlantConfig(int index, bool simplified)
{
  if (index < 0 || index >= kDefaultPlantCount)
    throw InvalidArgumentError("default plant index " + std::to_string(index) +
                               " is outside [0, " +
                               std::to_string(kDefaultPlantCount - 1) + "]");
  TomatoPlantGenerator::Config config;
  config.seed = static_cast<std::uint64_t>(index);
  config.growth_stage = static_cast<double>(index) / (kDefaultPlantCount - 1);
  config.simplified = simplified;
  return config;
}

std::vector<TomatoPlantGenerator::Config> defaultPlantSet(bool simplified)
{
  std::vector<TomatoPlantGenerator::Config> set;
  for (int i = 0; i < kDefaultPlantCount; ++i)
    set.push_back(defaultPlantConfig(i, simplified));
  return set;
}

// -----------------------------------------------------------------------------------
// Generation

Plant TomatoPlantGenerator::generate() const
{
  const Config& cfg = config_;
  const double stage = cfg.growth_stage;
  const double detail = cfg.mesh_detail;

  Plant plant;
  plant.name =
      "tomato_seed" + std::to_string(cfg.seed) + (cfg.simplified ? "_simplified" : "");
  PlantAnatomy& anatomy = plant.anatomy;
  TriangleMesh& mesh = plant.mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(150000 * detail * detail));
  const auto expected_triangles = static_cast<std::size_t>(300000 * detail * detail);
  mesh.triangles.reserve(expected_triangles);
  mesh.labels.reserve(expected_triangles);
  mesh.node_ids.reserve(expected_triangles);
  MeshBuilder mb(mesh);

  // --- Plant-level traits (one stream; the order of draws is part of the format) ---
  Draws plant_draws(cfg.seed, kPlantStream, cfg.variation);
  StemShape stem;
  stem.height = clamp(lerp(0.465, 0.635, stage) + plant_draws.jitter(0.015),
                      kStemHeightMin, kStemHeightMax);
  stem.r_base = clamp(lerp(0.0030, 0.0040, stage) + plant_draws.jitter(0.0003),
                      kStemRadiusMin, kStemRadiusMax);
  stem.r_top = std::max(kStemRadiusMin, stem.r_base * (0.75 + plant_draws.jitter(0.05)));
  stem.bend_dir = horizontal(2.0 * M_PI * plant_draws.unit());
  stem.wave_dir = horizontal(2.0 * M_PI * plant_draws.unit());
  // Bounded so that the stem stays within 1.6 cm of the vertical through its base and
  // the paper's 5 cm wide main-stem box holds it.
  stem.bend_m = 0.005 + plant_draws.jitter(0.005);
  stem.wave_m = 0.0015 + plant_draws.jitter(0.0015);
  stem.wave_freq = 2.0 * M_PI * (1.0 + plant_draws.jitter(0.3));
  stem.wave_phase = 2.0 * M_PI * plant_draws.unit();
  const double azimuth0 = 2.0 * M_PI * plant_draws.unit();
  const double divergence = cfg.divergence_angle_rad + plant_draws.jitter(2.5 * kDeg);
  // Internodes lengthen as the plant develops; the top ones are still elongating.
  const double internode = lerp(0.040, 0.047, stage) * plant_draws.factor(0.06);
  const double first_node_min = lerp(0.05, 0.08, stage) * plant_draws.factor(0.1);
  const double apex_gap = lerp(0.02, 0.03, stage) + plant_draws.jitter(0.004);
  const double leaf_length_max = clamp(lerp(0.24, 0.34, stage) * plant_draws.factor(0.04),
                                       kLeafLengthMin, kLeafLengthMax);
  // First truss above leaf 3-6 (0-based; earlier in older plants, so that they carry
  // more trusses), then one every third leaf. docs/plants.md: why earlier than in crops.
  const int first_truss_leaf = static_cast<int>(
      clamp(std::round(lerp(5.5, 3.5, stage) + plant_draws.jitter(1.0)), 3, 6));

  // The apical cone of the stem reaches `height`; the last ring sits below it.
  const double cone_height = 1.2 * stem.r_top;
  const double z_top_ring = stem.height - cone_height;

  // Node heights, from the apex down: the three youngest internodes are short.
  {
    const double apical[] = {0.45, 0.65, 0.85};
    std::vector<double> z_down{stem.height - apex_gap};
    for (int i = 0;; ++i) {
      const double f = i < 3 ? apical[i] : 1.0;
      const double z = z_down.back() - internode * f * plant_draws.factor(0.12);
      if (z < first_node_min)
        break;
      z_down.push_back(z);
    }
    stem.node_z.assign(z_down.rbegin(), z_down.rend());
  }
  const int leaf_count = static_cast<int>(stem.node_z.size());

  // --- Stem mesh and axis ---
  {
    mb.beginPart(PartLabel::stem, "stem");
    const double step = 0.002 / detail;
    const int rings = std::max(2, static_cast<int>(std::ceil(z_top_ring / step)) + 1);
    std::vector<Vec3> axis;
    std::vector<double> radius;
    for (int i = 0; i < rings; ++i) {
      const double z = z_top_ring * i / (rings - 1);
      axis.push_back(stem.center(z));
      radius.push_back(stem.radius(z));
    }
    // Horizontal rings: the base ring lies exactly on the base plane z = 0.
    const int segments = scaled(32, detail, 8);
    const std::uint32_t top_ring =
        mb.tube(axis, radius, segments, Cap::flat, Cap::open, Vec3::UnitX(), true);
    // The apex is the top of the centre line: the stem is exactly `height` tall.
    const Vec3 apex = stem.center(stem.height);
    mb.capFan(top_ring, segments, apex, false);
    // The anatomy's axis: every centimetre, then the apex.
    const int n = std::max(2, static_cast<int>(std::ceil(z_top_ring / 0.01)) + 1);
    for (int i = 0; i < n; ++i) {
      const double z = z_top_ring * i / (n - 1);
      anatomy.stem_axis.push_back(stem.center(z));
      anatomy.stem_radius_m.push_back(stem.radius(z));
    }
    anatomy.stem_axis.push_back(apex);
    anatomy.stem_radius_m.push_back(0.0);
    anatomy.stem_height_m = apex.z();
  }

  const int tube_segments = scaled(12, detail, 6);
  const double organ_step = 0.003 / detail;
  const int leaflet_rows = scaled(48, detail, 8);
  const int leaflet_columns = 2 * scaled(10, detail, 2);
  std::vector<double> leaf_azimuth(leaf_count);

  // --- Leaves ---
  for (int k = 0; k < leaf_count; ++k) {
    Draws d(cfg.seed, kLeafStream + static_cast<std::uint64_t>(k), cfg.variation);
    const double q = leaf_count > 1 ? static_cast<double>(k) / (leaf_count - 1) : 0.5;
    const int age = leaf_count - 1 - k; // 0 = youngest, at the apex
    const double z = stem.node_z[k];
    const double r_stem = stem.radius(z);
    const Vec3 stem_point = stem.center(z);

    // Young leaves at the apex and the first leaves of the plant are smaller.
    const double apical_factor[] = {0.5, 0.65, 0.8, 0.92};
    double size_factor = age < 4 ? apical_factor[age] : 1.0;
    if (k < 2)
      size_factor = std::min(size_factor, k == 0 ? 0.8 : 0.9);
    Leaf leaf;
    leaf.length_m = clamp(leaf_length_max * size_factor * d.factor(0.06), kLeafLengthMin,
                          kLeafLengthMax);
    const double L = leaf.length_m;
    const double l_rel = (L - kLeafLengthMin) / (kLeafLengthMax - kLeafLengthMin);

    OrganAxis ax;
    ax.psi0 = leaf_azimuth[k] = azimuth0 + k * divergence + d.jitter(4.0 * kDeg);
    // Lower leaves spread flatter, young ones stand up.
    ax.theta0 = (lerp(28.0, 45.0, q) + d.jitter(6.0)) * kDeg;
    // Longer leaves droop more under their weight.
    ax.droop = (lerp(80.0, 115.0, l_rel) + d.jitter(10.0)) * kDeg;
    ax.swing = d.jitter(12.0 * kDeg);
    ax.length = L;
    ax.s_junction = 0.5 * r_stem / portableCos(ax.theta0);

    const double petiole_fraction = 0.22 + d.jitter(0.04);
    const int pairs =
        static_cast<int>(clamp(std::round(2.0 + 2.0 * l_rel + d.jitter(0.5)), 2, 4));
    leaf.full_leaflet_count = 2 * pairs + 1;
    const double r_petiole =
        lerp(0.0020, 0.0028, stage) * (0.75 + 0.25 * l_rel) * d.factor(0.08);
    const double r_tip = 0.0008;
    // The terminal leaflet is the largest; pairs grow towards the tip.
    const double terminal_length = clamp(lerp(0.045, 0.088, l_rel) * d.factor(0.06),
                                         kLeafletLengthMin, kLeafletLengthMax);

    // Leaflet traits, drawn for every leaflet (also those a simplified plant drops, so
    // the draws never depend on it): pairs from the petiole on, left then right, then
    // the terminal leaflet.
    struct LeafletDraw {
      int pair = 0, side = 0;
      bool terminal = false;
      double length, width, insertion, tilt, roll, bend, cup, twist, teeth, teeth_phase;
    };
    std::vector<LeafletDraw> traits;
    for (int j = 0; j <= pairs; ++j)
      for (int side = -1; side <= (j == pairs ? -1 : 1); side += 2) {
        LeafletDraw t;
        t.pair = j;
        t.terminal = j == pairs;
        t.side = t.terminal ? 0 : side;
        const double size =
            t.terminal ? 1.0 : (0.65 + 0.3 * (j + 1.0) / pairs) * d.factor(0.06);
        t.length = clamp(terminal_length * size, kLeafletLengthMin, kLeafletLengthMax);
        t.width = clamp((0.02 + (t.length - 0.03) / 0.06 * 0.02) * d.factor(0.1),
                        kLeafletWidthMin, kLeafletWidthMax);
        const double insertion = (62.0 + d.jitter(12.0)) * kDeg;
        t.insertion =
            t.terminal ? 0.0 : insertion; // the terminal one continues the rachis
        t.tilt = (-3.0 + d.jitter(12.0)) * kDeg;
        t.roll = d.jitter(20.0 * kDeg);
        t.bend = 0.12 + d.jitter(0.07);
        t.cup = -0.1 + d.jitter(0.2);
        t.twist = d.jitter(15.0 * kDeg);
        t.teeth = 7.0 + std::floor(5.999 * d.unit());
        t.teeth_phase = d.unit();
        traits.push_back(t);
      }

    const double last_gap = clamp(0.4 * terminal_length, 0.015, 0.04);
    auto radiusAt = [&](double s) { return lerp(r_petiole, r_tip, ax.u(s)); };
    auto placeLeaflets = [&]() {
      const double s_first = ax.s_junction + petiole_fraction * L;
      const double s_last = ax.end() - last_gap;
      std::vector<LeafletShape> blades;
      for (const LeafletDraw& t : traits) {
        LeafletShape b;
        b.terminal = t.terminal;
        b.length = t.length, b.width = t.width, b.bend = t.bend, b.cup = t.cup;
        b.twist = t.twist, b.teeth = t.teeth, b.teeth_phase = t.teeth_phase;
        const double s =
            t.terminal
                ? ax.end()
                : (pairs > 1
                       ? lerp(s_first, s_last, static_cast<double>(t.pair) / (pairs - 1))
                       : s_last);
        const Vec3 tangent = ax.direction(s);
        Vec3 up = Vec3::UnitZ() - tangent.z() * tangent;
        up = up.squaredNorm() > 1e-12 ? up.normalized() : tangent.unitOrthogonal();
        const Vec3 lateral = up.cross(tangent); // left of the rachis, seen from above
        double si, ci, st, ct, sr, cr;
        portableSinCos(t.insertion, si, ci);
        portableSinCos(t.tilt, st, ct);
        portableSinCos(t.roll, sr, cr);
        const Vec3 d_flat = (ci * tangent + si * t.side * lateral).normalized();
        b.d = (ct * d_flat + st * up).normalized();
        // The blade's cross axis is horizontal: leaflets turn their upper side to the
        // light whatever the slope of the rachis.
        Vec3 e0 = Vec3::UnitZ().cross(b.d);
        e0 = e0.squaredNorm() > 1e-12 ? e0.normalized() : lateral;
        b.e = cr * e0 + sr * b.d.cross(e0);
        b.n = b.d.cross(b.e);
        b.base = ax.at(s) + (t.terminal ? 0.0 : radiusAt(s)) * d_flat;
        blades.push_back(b);
      }
      return blades;
    };
    auto lowest = [&](const std::vector<LeafletShape>& blades) {
      double z_min = INFINITY;
      for (const Vec3& p : ax.points)
        z_min = std::min(z_min, p.z());
      for (const LeafletShape& b : blades)
        for (double u : {0.25, 0.5, 0.75, 1.0})
          for (double v : {-1.0, 0.0, 1.0})
            z_min = std::min(z_min, b.point(u, v, 0.0, 1.0).z() - 0.2 * b.width);
      return z_min;
    };
    // Nothing may hang below the base (into the pot): a low leaf that would stands up
    // more and droops less.
    const Vec3 start = stem_point + 0.5 * r_stem * horizontal(ax.psi0);
    std::vector<LeafletShape> blades;
    for (int attempt = 0;; ++attempt) {
      ax.build(start, organ_step);
      blades = placeLeaflets();
      if (attempt == 16 || lowest(blades) >= kMinPartHeight)
        break;
      ax.theta0 += 4.0 * kDeg;
      ax.droop *= 0.9;
    }

    leaf.node.leaf_index = k;
    leaf.node.stem_point = stem_point;
    leaf.node.position = ax.at(ax.s_junction);
    leaf.node.petiole_direction = ax.direction(0.0);
    leaf.axis = ax.points;

    mb.beginPart(PartLabel::petiole, "leaf_" + twoDigits(k) + "_petiole");
    {
      std::vector<double> radius;
      for (std::size_t i = 0; i < ax.points.size(); ++i)
        radius.push_back(radiusAt(ax.ds * static_cast<double>(i)));
      mb.tube(ax.points, radius, tube_segments, Cap::open, Cap::pointed);
    }

    // Simplified: drop one leaflet of every pair, alternating the side from pair to pair
    // and from leaf to leaf; the terminal leaflet stays.
    const int first_side = (k % 2 == 0) ? 1 : -1;
    for (std::size_t i = 0; i < blades.size(); ++i) {
      const LeafletDraw& t = traits[i];
      const LeafletShape& b = blades[i];
      const int dropped_side = (t.pair % 2 == 0) ? first_side : -first_side;
      if (cfg.simplified && !t.terminal && t.side == dropped_side)
        continue;
      mb.beginPart(PartLabel::leaflet,
                   "leaf_" + twoDigits(k) + "_leaflet_" + std::to_string(i));
      addLeaflet(mb, b, leaflet_rows, leaflet_columns);
      double ts, tc;
      portableSinCos(b.twist, ts, tc);
      leaf.leaflets.push_back(
          {b.base, b.point(1.0, 0.0, ts, tc), b.length, b.width, b.terminal});
    }
    anatomy.leaves.push_back(std::move(leaf));
  }

  // --- Trusses: on the internode above leaf first_truss_leaf + 3 i, as long as two
  // leaves grow above (younger trusses are flower buds, not modelled) ---
  const int peduncle_segments = scaled(10, detail, 6);
  const int pedicel_segments = scaled(8, detail, 5);
  const int fruit_rings = scaled(20, detail, 6);
  const int fruit_segments = scaled(36, detail, 8);
  int truss_index = 0;
  for (int k = first_truss_leaf; k + 2 < leaf_count; k += 3, ++truss_index) {
    Draws d(cfg.seed, kTrussStream + static_cast<std::uint64_t>(truss_index),
            cfg.variation);
    const double z = lerp(stem.node_z[k], stem.node_z[k + 1], 0.5 + d.jitter(0.15));
    const double r_stem = stem.radius(z);

    // Fruit: the lowest truss is the oldest and has the largest fruit.
    const int fruit_count = static_cast<int>(
        clamp(std::round(lerp(3.0, 5.5, stage) - 0.5 * truss_index + d.jitter(1.0)),
              kFruitsMin, kFruitsMax));
    const double r_first =
        lerp(0.018, 0.029, stage) * (1.0 - 0.18 * truss_index) * d.factor(0.05);
    std::vector<double> fruit_r;
    for (int i = 0; i < fruit_count; ++i)
      fruit_r.push_back(clamp(r_first * (1.0 - 0.05 * i) * d.factor(0.04),
                              kFruitRadiusMin, kFruitRadiusMax));

    // Away from the neighbouring leaves: the azimuth farthest from leaves k-1..k+2.
    double best = 0.0, best_score = -1.0;
    for (int m = 0; m < 72; ++m) {
      const double a = m * 5.0 * kDeg;
      double score = M_PI;
      for (int n = std::max(0, k - 1); n <= std::min(leaf_count - 1, k + 2); ++n)
        score = std::min(score, angularDistance(a, leaf_azimuth[n]));
      if (score > best_score)
        best_score = score, best = a;
    }
    OrganAxis ax;
    ax.psi0 = best + d.jitter(10.0 * kDeg);
    ax.theta0 = (25.0 + d.jitter(10.0)) * kDeg;
    ax.droop = (65.0 + d.jitter(10.0)) * kDeg;
    ax.droop_linear = 0.0;
    ax.swing = d.jitter(10.0 * kDeg);
    ax.s_junction = 0.5 * r_stem / portableCos(ax.theta0);
    const double bare = 0.04 + 1.2 * fruit_r.front() + d.jitter(0.01);
    std::vector<double> s_fruit{ax.s_junction + bare};
    for (int i = 1; i < fruit_count; ++i)
      s_fruit.push_back(s_fruit.back() + 0.8 * (fruit_r[i - 1] + fruit_r[i]));
    ax.length = s_fruit.back() - ax.s_junction + 0.01;
    const Vec3 stem_point = stem.center(z);
    ax.build(stem_point + 0.5 * r_stem * horizontal(ax.psi0), organ_step);

    Truss truss;
    truss.leaf_below = k;
    truss.attachment = ax.at(ax.s_junction);
    truss.peduncle = ax.points;
    const std::string prefix = "truss_" + std::to_string(truss_index);
    const double r_peduncle = lerp(0.0018, 0.0025, stage) * d.factor(0.08);
    mb.beginPart(PartLabel::peduncle, prefix + "_peduncle");
    {
      std::vector<double> radius;
      for (std::size_t i = 0; i < ax.points.size(); ++i)
        radius.push_back(lerp(r_peduncle, 0.0012, ax.u(ax.ds * static_cast<double>(i))));
      mb.tube(ax.points, radius, peduncle_segments, Cap::open, Cap::pointed);
    }
    int side = d.unit() < 0.5 ? -1 : 1;
    for (int i = 0; i < fruit_count; ++i, side = -side) {
      const double r = fruit_r[i];
      const double r_z = 0.88 * r; // tomato fruit are slightly oblate
      const double pedicel = 0.011 + d.jitter(0.003);
      const Vec3 q = ax.at(s_fruit[i]);
      Vec3 lateral = Vec3::UnitZ().cross(ax.direction(s_fruit[i]));
      lateral = lateral.squaredNorm() > 1e-12 ? lateral.normalized() : Vec3::UnitX();
      const Vec3 h = (-Vec3::UnitZ() + 0.8 * side * lateral).normalized();
      // Distance from the spheroid's centre to its surface along h.
      const double r_h = 1.0 / std::sqrt((h.x() * h.x() + h.y() * h.y()) / (r * r) +
                                         h.z() * h.z() / (r_z * r_z));
      const Vec3 center = q + (pedicel + r_h) * h;
      mb.beginPart(PartLabel::peduncle, prefix + "_pedicel_" + std::to_string(i));
      mb.tube({q, q + 0.5 * (pedicel + 0.2 * r_h) * h, center - 0.8 * r_h * h},
              {0.0012, 0.0011, 0.0011}, pedicel_segments, Cap::open, Cap::open);
      mb.beginPart(PartLabel::fruit, prefix + "_fruit_" + std::to_string(i));
      mb.spheroid(center, r, r_z, fruit_rings, fruit_segments);
      truss.fruits.push_back({center, r});
    }
    anatomy.trusses.push_back(std::move(truss));
  }

  double top = 0.0;
  for (const auto& v : mesh.vertices)
    top = std::max(top, static_cast<double>(v.z()));
  anatomy.top_height_m = top;
  return plant;
}

} // namespace plantnbv
