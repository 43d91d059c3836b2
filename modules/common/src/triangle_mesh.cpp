#include <string>
#include <utility>

#include <Eigen/Geometry>

#include <plantnbv/common/error.h>
#include <plantnbv/common/triangle_mesh.h>

namespace plantnbv {

namespace {
constexpr const char* kPartNames[] = {"unknown",  "stem",  "petiole",    "leaflet",
                                      "peduncle", "fruit", "background", "flower"};
constexpr std::size_t kPartCount = sizeof(kPartNames) / sizeof(kPartNames[0]);
static_assert(kPartCount == std::size_t(kLastPartLabel) + 1, "a name for every label");
} // namespace

const char* partLabelName(PartLabel label)
{
  const auto i = static_cast<std::size_t>(label);
  if (i >= kPartCount)
    throw InvalidArgumentError("unknown part label value " + std::to_string(i));
  return kPartNames[i];
}

bool isPlantPart(std::uint32_t label)
{
  return label != std::uint32_t(PartLabel::unknown) &&
         label != std::uint32_t(PartLabel::background) &&
         label <= std::uint32_t(kLastPartLabel);
}

PartLabel partLabelFromName(const std::string& name)
{
  for (std::size_t i = 0; i < kPartCount; ++i)
    if (name == kPartNames[i])
      return static_cast<PartLabel>(i);
  std::string known;
  for (std::size_t i = 0; i < kPartCount; ++i)
    known += (i ? ", " : "") + std::string(kPartNames[i]);
  throw InvalidArgumentError("unknown part label '" + name + "' (expected one of " +
                             known + ")");
}

double TriangleMesh::triangleArea(std::size_t t) const
{
  const auto& tri = triangles[t];
  const Eigen::Vector3d a = vertices[tri[0]].cast<double>();
  const Eigen::Vector3d b = vertices[tri[1]].cast<double>();
  const Eigen::Vector3d c = vertices[tri[2]].cast<double>();
  return 0.5 * (b - a).cross(c - a).norm();
}

void TriangleMesh::bounds(Eigen::Vector3f& min, Eigen::Vector3f& max) const
{
  if (vertices.empty())
    throw InvalidArgumentError("the bounds of a mesh without vertices are undefined");
  min = max = vertices.front();
  for (const auto& v : vertices) {
    min = min.cwiseMin(v);
    max = max.cwiseMax(v);
  }
}

void TriangleMesh::append(const TriangleMesh& other)
{
  const auto vertex_offset = static_cast<std::uint32_t>(vertices.size());
  const std::size_t old_count = triangles.size();
  const std::size_t new_count = old_count + other.triangles.size();
  vertices.insert(vertices.end(), other.vertices.begin(), other.vertices.end());
  for (auto tri : other.triangles) {
    for (auto& i : tri)
      i += vertex_offset;
    triangles.push_back(tri);
  }
  // Per-triangle arrays stay complete or empty: the side that had none gets defaults.
  if (hasLabels() || other.hasLabels()) {
    labels.resize(old_count, PartLabel::unknown);
    labels.insert(labels.end(), other.labels.begin(), other.labels.end());
    labels.resize(new_count, PartLabel::unknown);
  }
  const auto node_offset = static_cast<std::uint32_t>(node_names.size());
  node_names.insert(node_names.end(), other.node_names.begin(), other.node_names.end());
  for (auto [mine, theirs] : {std::pair{&geometry_names, &other.geometry_names},
                              std::pair{&material_names, &other.material_names}}) {
    if (mine->empty() && theirs->empty())
      continue;
    mine->resize(node_offset);
    mine->insert(mine->end(), theirs->begin(), theirs->end());
    mine->resize(node_names.size());
  }
  if (node_ids.empty() && other.node_ids.empty())
    return;
  const auto unnamed = static_cast<std::uint32_t>(node_names.size());
  bool used_unnamed = node_ids.empty() && old_count > 0;
  node_ids.resize(old_count, unnamed);
  for (auto id : other.node_ids)
    node_ids.push_back(id + node_offset);
  used_unnamed = used_unnamed || (other.node_ids.empty() && !other.triangles.empty());
  node_ids.resize(new_count, unnamed);
  if (used_unnamed) {
    node_names.emplace_back("");
    for (auto* names : {&geometry_names, &material_names})
      if (!names->empty())
        names->resize(node_names.size());
  }
}

std::array<std::string, 3> TriangleMesh::namesOf(std::uint32_t id) const
{
  auto at = [id](const std::vector<std::string>& names) {
    return id < names.size() ? names[id] : std::string();
  };
  return {at(node_names), at(geometry_names), at(material_names)};
}

void TriangleMesh::validate() const
{
  const std::size_t n = vertices.size();
  for (std::size_t i = 0; i < n; ++i)
    if (!vertices[i].allFinite())
      throw FormatError("vertex " + std::to_string(i) + " is not finite");
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (auto i : triangles[t])
      if (i >= n)
        throw FormatError("triangle " + std::to_string(t) + " refers to vertex " +
                          std::to_string(i) + " of " + std::to_string(n));
  if (!labels.empty() && labels.size() != triangles.size())
    throw FormatError("mesh has " + std::to_string(labels.size()) + " labels for " +
                      std::to_string(triangles.size()) + " triangles");
  if (!node_ids.empty() && node_ids.size() != triangles.size())
    throw FormatError("mesh has " + std::to_string(node_ids.size()) + " node ids for " +
                      std::to_string(triangles.size()) + " triangles");
  for (const auto* names : {&geometry_names, &material_names})
    if (!names->empty() && names->size() != node_names.size())
      throw FormatError("mesh has " + std::to_string(names->size()) +
                        " geometry or material names for " +
                        std::to_string(node_names.size()) + " node names");
  for (auto id : node_ids)
    if (id >= node_names.size())
      throw FormatError("node id " + std::to_string(id) + " exceeds the " +
                        std::to_string(node_names.size()) + " node names");
}

} // namespace plantnbv
