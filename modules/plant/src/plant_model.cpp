#include <regex>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_model.h>

namespace plantnbv {

std::vector<PartLabelRule> parsePartLabelRules(const std::string& spec)
{
  std::vector<PartLabelRule> rules;
  std::size_t start = 0;
  while (start <= spec.size()) {
    const std::size_t end = std::min(spec.find(',', start), spec.size());
    const std::string pair = spec.substr(start, end - start);
    const std::size_t eq = pair.find('=');
    if (eq == std::string::npos || eq + 1 == pair.size())
      throw InvalidArgumentError("label rule '" + pair +
                                 "' must be part=regex, e.g. stem=Branch.*");
    PartLabelRule rule;
    rule.label = partLabelFromName(pair.substr(0, eq));
    rule.pattern = pair.substr(eq + 1);
    try {
      std::regex check(rule.pattern);
    } catch (const std::regex_error& e) {
      throw InvalidArgumentError("label rule '" + pair +
                                 "': invalid regular expression (" + e.what() + ")");
    }
    rules.push_back(rule);
    start = end + 1;
  }
  return rules;
}

std::vector<std::size_t> applyPartLabelRules(TriangleMesh& mesh,
                                             const std::vector<PartLabelRule>& rules)
{
  std::vector<std::regex> regexes;
  for (const auto& r : rules)
    regexes.emplace_back(r.pattern);
  // Match each node id's names once, not each triangle's.
  std::vector<int> rule_of_node(mesh.node_names.size(), -1);
  for (std::size_t n = 0; n < mesh.node_names.size(); ++n) {
    const auto names = mesh.namesOf(static_cast<std::uint32_t>(n));
    for (std::size_t r = 0; r < rules.size() && rule_of_node[n] < 0; ++r)
      for (std::size_t k = 0; k < names.size() && rule_of_node[n] < 0; ++k)
        if ((k == 0 || !names[k].empty()) && std::regex_match(names[k], regexes[r]))
          rule_of_node[n] = static_cast<int>(r);
  }
  if (mesh.labels.empty())
    mesh.labels.assign(mesh.size(), PartLabel::unknown);
  std::vector<std::size_t> counts(rules.size(), 0);
  for (std::size_t t = 0; t < mesh.node_ids.size(); ++t) {
    const int r = rule_of_node[mesh.node_ids[t]];
    if (r >= 0) {
      mesh.labels[t] = rules[r].label;
      ++counts[r];
    }
  }
  return counts;
}

namespace {

/// Moves the plant's geometry so that the centre of its bounding box's bottom face is the
/// origin (or records it as the base with keep_frame), and sets the axis-only anatomy.
void placeAtBottomCentre(Plant& plant, bool keep_frame)
{
  Eigen::Vector3f lo, hi;
  plant.bounds(lo, hi);
  const Eigen::Vector3d bottom_centre(0.5 * (double(lo.x()) + hi.x()),
                                      0.5 * (double(lo.y()) + hi.y()), lo.z());
  if (!keep_frame)
    for (auto* points : {&plant.mesh.vertices, &plant.scan_points})
      for (auto& v : *points)
        v = (v.cast<double>() - bottom_centre).cast<float>();
  plant.base_position = keep_frame ? bottom_centre : Eigen::Vector3d::Zero();
  const double height = double(hi.z()) - lo.z();
  plant.anatomy.stem_axis = {plant.base_position,
                             plant.base_position + Eigen::Vector3d(0, 0, height)};
  plant.anatomy.stem_radius_m = {0.0, 0.0};
  plant.anatomy.stem_height_m = height;
  plant.anatomy.top_height_m = height;
}

} // namespace

Plant plantFromMesh(TriangleMesh mesh, const std::string& name, bool keep_frame)
{
  if (mesh.empty())
    throw InvalidArgumentError("plant model '" + name + "' has no triangles");
  Plant plant;
  plant.name = name;
  plant.mesh = std::move(mesh);
  placeAtBottomCentre(plant, keep_frame);
  return plant;
}

Plant plantFromScan(std::vector<Eigen::Vector3f> points, std::vector<PartLabel> labels,
                    const std::string& name, bool keep_frame)
{
  if (points.empty())
    throw InvalidArgumentError("plant scan '" + name + "' has no points");
  if (!labels.empty() && labels.size() != points.size())
    throw InvalidArgumentError("plant scan '" + name + "' has " +
                               std::to_string(labels.size()) + " labels for " +
                               std::to_string(points.size()) + " points");
  for (const auto& p : points)
    if (!p.allFinite())
      throw InvalidArgumentError("plant scan '" + name + "' has non-finite points");
  Plant plant;
  plant.name = name;
  plant.scan_points = std::move(points);
  plant.scan_labels = std::move(labels);
  placeAtBottomCentre(plant, keep_frame);
  return plant;
}

} // namespace plantnbv
