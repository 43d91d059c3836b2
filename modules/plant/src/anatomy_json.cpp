#include <cmath>
#include <cstdint>

#include <climits>
#include <nlohmann/json.hpp>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/anatomy_json.h>

namespace plantnbv {

namespace {

using nlohmann::json;

json vec(const Eigen::Vector3d& v)
{
  return json::array({v.x(), v.y(), v.z()});
}

json polyline(const std::vector<Eigen::Vector3d>& points)
{
  json a = json::array();
  for (const auto& p : points)
    a.push_back(vec(p));
  return a;
}

/// Typed access to a JSON tree that names the path of whatever is wrong.
class Reader {
public:
  Reader(const json& j, std::string path) : j_(j), path_(std::move(path)) {}

  Reader operator[](const char* key) const
  {
    if (!j_.is_object() || !j_.contains(key))
      fail(std::string("missing key '") + key + "'");
    return Reader(j_.at(key), path_.empty() ? key : path_ + "." + key);
  }
  Reader at(std::size_t i) const
  {
    return Reader(j_.at(i), path_ + "[" + std::to_string(i) + "]");
  }
  std::size_t size() const
  {
    if (!j_.is_array())
      fail("expected an array");
    return j_.size();
  }
  double number() const
  {
    if (!j_.is_number() || !std::isfinite(j_.get<double>()))
      fail("expected a finite number");
    return j_.get<double>();
  }
  int integer() const
  {
    // get<int>() would wrap a larger integer around silently.
    const bool in_range = j_.is_number_unsigned()
                              ? j_.get<std::uint64_t>() <= INT_MAX
                              : j_.is_number_integer() &&
                                    j_.get<std::int64_t>() >= INT_MIN &&
                                    j_.get<std::int64_t>() <= INT_MAX;
    if (!in_range)
      fail("expected an integer in the int range");
    return j_.get<int>();
  }
  bool boolean() const
  {
    if (!j_.is_boolean())
      fail("expected true or false");
    return j_.get<bool>();
  }
  std::string string() const
  {
    if (!j_.is_string())
      fail("expected a string");
    return j_.get<std::string>();
  }
  Eigen::Vector3d vec3() const
  {
    if (!j_.is_array() || j_.size() != 3)
      fail("expected 3 numbers");
    return Eigen::Vector3d(at(0).number(), at(1).number(), at(2).number());
  }
  std::vector<Eigen::Vector3d> polyline() const
  {
    std::vector<Eigen::Vector3d> points(size());
    for (std::size_t i = 0; i < points.size(); ++i)
      points[i] = at(i).vec3();
    return points;
  }
  [[noreturn]] void fail(const std::string& what) const
  {
    throw FormatError("anatomy JSON: " +
                      (path_.empty() ? std::string("top level") : path_) + ": " + what);
  }

private:
  const json& j_;
  std::string path_;
};

} // namespace

std::string anatomyToJson(const Plant& plant)
{
  const PlantAnatomy& a = plant.anatomy;
  json j;
  j["format"] = "plantnbv-anatomy";
  j["version"] = 1;
  j["name"] = plant.name;
  j["base_position"] = vec(plant.base_position);
  j["yaw_rad"] = plant.yaw_rad;
  j["stem"] = {{"axis", polyline(a.stem_axis)},
               {"radius_m", a.stem_radius_m},
               {"height_m", a.stem_height_m},
               {"top_height_m", a.top_height_m}};
  j["leaves"] = json::array();
  for (const Leaf& leaf : a.leaves) {
    json leaflets = json::array();
    for (const Leaflet& l : leaf.leaflets)
      leaflets.push_back({{"base", vec(l.base)},
                          {"tip", vec(l.tip)},
                          {"length_m", l.length_m},
                          {"width_m", l.width_m},
                          {"terminal", l.terminal}});
    j["leaves"].push_back({{"node",
                            {{"leaf_index", leaf.node.leaf_index},
                             {"position", vec(leaf.node.position)},
                             {"stem_point", vec(leaf.node.stem_point)},
                             {"petiole_direction", vec(leaf.node.petiole_direction)}}},
                           {"axis", polyline(leaf.axis)},
                           {"length_m", leaf.length_m},
                           {"full_leaflet_count", leaf.full_leaflet_count},
                           {"leaflets", leaflets}});
  }
  j["trusses"] = json::array();
  for (const Truss& t : a.trusses) {
    json fruits = json::array();
    for (const Fruit& f : t.fruits)
      fruits.push_back({{"center", vec(f.center)}, {"radius_m", f.radius_m}});
    j["trusses"].push_back({{"leaf_below", t.leaf_below},
                            {"attachment", vec(t.attachment)},
                            {"peduncle", polyline(t.peduncle)},
                            {"fruits", fruits}});
  }
  return j.dump(1);
}

void anatomyFromJson(const std::string& text, Plant& plant)
{
  json j;
  try {
    j = json::parse(text);
  } catch (const json::exception& e) {
    // parse_error, and out_of_range for a number beyond double (found by fuzzing).
    throw FormatError(std::string("anatomy JSON: not JSON (") + e.what() + ")");
  }
  const Reader r(j, "");
  if (r["format"].string() != "plantnbv-anatomy")
    r["format"].fail("expected \"plantnbv-anatomy\"");
  if (r["version"].integer() != 1)
    r["version"].fail("only version 1 is known");

  Plant out;
  out.name = r["name"].string();
  out.base_position = r["base_position"].vec3();
  out.yaw_rad = r["yaw_rad"].number();
  PlantAnatomy& a = out.anatomy;
  const Reader stem = r["stem"];
  a.stem_axis = stem["axis"].polyline();
  for (std::size_t i = 0; i < stem["radius_m"].size(); ++i)
    a.stem_radius_m.push_back(stem["radius_m"].at(i).number());
  a.stem_height_m = stem["height_m"].number();
  a.top_height_m = stem["top_height_m"].number();

  const Reader leaves = r["leaves"];
  for (std::size_t i = 0; i < leaves.size(); ++i) {
    const Reader l = leaves.at(i);
    Leaf leaf;
    leaf.node.leaf_index = l["node"]["leaf_index"].integer();
    leaf.node.position = l["node"]["position"].vec3();
    leaf.node.stem_point = l["node"]["stem_point"].vec3();
    leaf.node.petiole_direction = l["node"]["petiole_direction"].vec3();
    leaf.axis = l["axis"].polyline();
    leaf.length_m = l["length_m"].number();
    leaf.full_leaflet_count = l["full_leaflet_count"].integer();
    const Reader leaflets = l["leaflets"];
    for (std::size_t k = 0; k < leaflets.size(); ++k) {
      Leaflet f;
      f.base = leaflets.at(k)["base"].vec3();
      f.tip = leaflets.at(k)["tip"].vec3();
      f.length_m = leaflets.at(k)["length_m"].number();
      f.width_m = leaflets.at(k)["width_m"].number();
      f.terminal = leaflets.at(k)["terminal"].boolean();
      leaf.leaflets.push_back(f);
    }
    a.leaves.push_back(std::move(leaf));
  }
  const Reader trusses = r["trusses"];
  for (std::size_t i = 0; i < trusses.size(); ++i) {
    const Reader t = trusses.at(i);
    Truss truss;
    truss.leaf_below = t["leaf_below"].integer();
    truss.attachment = t["attachment"].vec3();
    truss.peduncle = t["peduncle"].polyline();
    const Reader fruits = t["fruits"];
    for (std::size_t k = 0; k < fruits.size(); ++k)
      truss.fruits.push_back(
          {fruits.at(k)["center"].vec3(), fruits.at(k)["radius_m"].number()});
    a.trusses.push_back(std::move(truss));
  }
  plant.name = std::move(out.name);
  plant.base_position = out.base_position;
  plant.yaw_rad = out.yaw_rad;
  plant.anatomy = std::move(out.anatomy);
}

} // namespace plantnbv
