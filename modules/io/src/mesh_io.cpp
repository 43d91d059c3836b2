#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <Eigen/Core>
#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <plantnbv/common/error.h>
#include <plantnbv/io/file_kind.h>
#include <plantnbv/io/mesh_io.h>

#include "io_util.h"

namespace plantnbv {
namespace io {

namespace {

const char* const kMeshExtensions = "expected .ply, .obj, .stl, .dae, .wrl or .vrml";

/// What a Collada file's top-level <asset> says about units and axes.
struct ColladaAsset {
  double meter = 1.0;            ///< metres per file unit (<unit meter="...">)
  bool has_unit = false;         ///< the file declares <unit meter="...">
  detail::Up up = detail::Up::y; ///< <up_axis>; Y_UP is Collada's default
};

std::string_view trim(std::string_view s)
{
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front())))
    s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back())))
    s.remove_suffix(1);
  return s;
}

/// The value of XML attribute `name` in the text of a start tag; false if absent.
bool attribute(std::string_view tag, std::string_view name, std::string_view& value)
{
  for (std::size_t at = tag.find(name); at != std::string_view::npos;
       at = tag.find(name, at + 1)) {
    // A whole attribute name: after a space, followed by "=" (spaces allowed around it).
    if (at == 0 || !std::isspace(static_cast<unsigned char>(tag[at - 1])))
      continue;
    std::size_t eq = at + name.size();
    while (eq < tag.size() && std::isspace(static_cast<unsigned char>(tag[eq])))
      ++eq;
    if (eq >= tag.size() || tag[eq] != '=')
      continue;
    const std::size_t quote = tag.find_first_of("\"'", eq);
    if (quote == std::string_view::npos)
      return false;
    const std::size_t close = tag.find(tag[quote], quote + 1);
    if (close == std::string_view::npos)
      return false;
    value = tag.substr(quote + 1, close - quote - 1);
    return true;
  }
  return false;
}

/// Reads <unit> and <up_axis> from the <asset> at the top of a Collada file. We apply
/// both ourselves, whatever Assimp does with them (see readWithAssimp).
ColladaAsset scanColladaAsset(const std::string& path, const std::string& head)
{
  // <asset> is the first child of <COLLADA>, so the first <asset> is the document's.
  ColladaAsset asset;
  const std::size_t begin = head.find("<asset");
  const std::size_t end = head.find("</asset>", begin == std::string::npos ? 0 : begin);
  if (begin == std::string::npos || end == std::string::npos)
    return asset;
  const std::string_view block = std::string_view(head).substr(begin, end - begin);
  const std::size_t unit = block.find("<unit");
  if (unit != std::string_view::npos) {
    const std::string_view tag = block.substr(unit, block.find('>', unit) - unit);
    std::string_view value;
    if (attribute(tag, "meter", value)) {
      double meter = 0.0;
      const std::string_view v = trim(value);
      const auto r = std::from_chars(v.data(), v.data() + v.size(), meter);
      if (r.ec != std::errc() || r.ptr != v.data() + v.size() || !std::isfinite(meter) ||
          meter <= 0.0)
        throw FormatError(detail::where(path) + "<unit meter=\"" + std::string(value) +
                          "\"> must be a positive number");
      asset.meter = meter;
      asset.has_unit = true;
    }
  }
  const std::size_t up = block.find("<up_axis>");
  if (up != std::string_view::npos) {
    const std::size_t value_begin = up + std::strlen("<up_axis>");
    const std::string_view value =
        trim(block.substr(value_begin, block.find('<', value_begin) - value_begin));
    if (value == "X_UP")
      asset.up = detail::Up::x;
    else if (value == "Y_UP")
      asset.up = detail::Up::y;
    else if (value == "Z_UP")
      asset.up = detail::Up::z;
    else
      throw FormatError(detail::where(path) + "<up_axis> '" + std::string(value) +
                        "' is not X_UP, Y_UP or Z_UP");
  }
  return asset;
}

/// The text with XML comments and CDATA sections blanked out (newlines kept, so line
/// numbers stay): Assimp's XML parser skips them, so the checks below must too.
std::string withoutCommentsAndCdata(const std::string& text)
{
  std::string out = text;
  for (std::size_t at = out.find("<!"); at != std::string::npos;
       at = out.find("<!", at)) {
    const char* close = out.compare(at, 4, "<!--") == 0        ? "-->"
                        : out.compare(at, 9, "<![CDATA[") == 0 ? "]]>"
                                                               : nullptr;
    if (!close) {
      ++at;
      continue;
    }
    const std::size_t end = out.find(close, at);
    const std::size_t stop =
        end == std::string::npos ? out.size() : end + std::strlen(close);
    for (std::size_t i = at; i < stop; ++i)
      if (out[i] != '\n')
        out[i] = ' ';
    at = stop;
  }
  return out;
}

/// Calls f(position, start tag text) for each start tag <name ...> of the text (the
/// whole name: not <name_more>).
template <typename F>
void forEachStartTag(std::string_view text, std::string_view name, F&& f)
{
  for (std::size_t at = text.find(name); at != std::string_view::npos;
       at = text.find(name, at + 1)) {
    const std::size_t after = at + name.size();
    if (at == 0 || text[at - 1] != '<' || after >= text.size() ||
        !(std::isspace(static_cast<unsigned char>(text[after])) || text[after] == '>' ||
          text[after] == '/'))
      continue;
    const std::size_t close = text.find('>', after);
    f(at - 1,
      text.substr(at - 1,
                  (close == std::string_view::npos ? text.size() : close) - (at - 1)));
  }
}

/// Refuses a Collada node graph that Assimp 5.2.5 would recurse through without end or
/// expand beyond memory: a <node> that instances (<instance_node url="#id">) itself or
/// an ancestor, directly or through other nodes; nodes nested deeper than kMaxDepth;
/// instances that multiply (a node instancing another twice, that one the next twice,
/// ...) to more than kMaxInstances nodes. `text` has its comments blanked; `fail(at,
/// what)` throws.
template <typename Fail>
void checkColladaNodeGraph(std::string_view text, Fail&& fail)
{
  constexpr std::size_t kMaxDepth = 256;
  constexpr std::uint64_t kMaxInstances = 1000000;
  struct Node {
    std::size_t at;                   ///< where its start tag is
    std::vector<std::size_t> targets; ///< nested nodes, then instanced ones (by index)
    std::vector<std::string> urls;    ///< the ids it instances, resolved below
  };
  std::vector<Node> nodes;
  std::unordered_map<std::string, std::size_t> ids;
  // The start tags, end tags and instances in file order.
  enum Kind { start, end, instance };
  std::vector<std::pair<std::size_t, Kind>> events;
  forEachStartTag(text, "node", [&](std::size_t at, std::string_view) {
    events.emplace_back(at, start);
  });
  forEachStartTag(text, "instance_node", [&](std::size_t at, std::string_view) {
    events.emplace_back(at, instance);
  });
  for (std::size_t at = text.find("</node>"); at != std::string_view::npos;
       at = text.find("</node>", at + 1))
    events.emplace_back(at, end);
  std::sort(events.begin(), events.end());
  std::vector<std::size_t> open; // the nodes enclosing the current position
  for (const auto& [at, kind] : events) {
    const std::size_t close = text.find('>', at);
    const std::string_view tag =
        text.substr(at, (close == std::string_view::npos ? text.size() : close) - at);
    if (kind == end) {
      if (!open.empty())
        open.pop_back();
      continue;
    }
    if (kind == instance) {
      std::string_view url;
      if (!open.empty() && attribute(tag, "url", url) && url.size() > 1 && url[0] == '#')
        nodes[open.back()].urls.emplace_back(url.substr(1));
      continue;
    }
    const std::size_t index = nodes.size();
    nodes.push_back({at, {}, {}});
    std::string_view id;
    if (attribute(tag, "id", id))
      ids.emplace(std::string(id), index);
    if (!open.empty())
      nodes[open.back()].targets.push_back(index);
    if (!tag.empty() && tag.back() == '/')
      continue; // <node ... /> holds nothing
    open.push_back(index);
    if (open.size() > kMaxDepth)
      fail(at, "<node>s nested more than " + std::to_string(kMaxDepth) + " deep");
  }
  for (Node& n : nodes)
    for (const std::string& url : n.urls) {
      const auto target = ids.find(url);
      if (target != ids.end()) // Assimp skips an instance of a node it does not find
        n.targets.push_back(target->second);
    }

  // Depth-first, without recursion: a target still on the path is a cycle; a node's
  // instance count is 1 + its targets' (saturating), known once all are done.
  std::vector<int> state(nodes.size(), 0); // 0 new, 1 on the path, 2 done
  std::vector<std::uint64_t> instances(nodes.size(), 1);
  std::vector<std::pair<std::size_t, std::size_t>> path; // (node, next target)
  for (std::size_t root = 0; root < nodes.size(); ++root) {
    if (state[root] != 0)
      continue;
    path.emplace_back(root, 0);
    state[root] = 1;
    while (!path.empty()) {
      auto& [n, next] = path.back();
      if (next < nodes[n].targets.size()) {
        const std::size_t t = nodes[n].targets[next++];
        if (state[t] == 1)
          fail(nodes[t].at, "<node> instances itself through <instance_node> (a cycle)");
        if (state[t] == 0) {
          state[t] = 1;
          path.emplace_back(t, 0);
        }
        continue;
      }
      for (const std::size_t t : nodes[n].targets)
        instances[n] = std::min(kMaxInstances + 1, instances[n] + instances[t]);
      if (instances[n] > kMaxInstances)
        fail(nodes[n].at, "<instance_node>s expand this <node> to more than " +
                              std::to_string(kMaxInstances) + " nodes");
      state[n] = 2;
      path.pop_back();
    }
  }
}

/// Refuses Collada files that make Assimp 5.2.5 loop forever, crash or read outside its
/// arrays (found by fuzzing):
/// - an index list (<p>) holding anything but digits and spaces;
/// - an array (<float_array>, ...) without a valid count attribute, or with a count
///   that the file cannot hold (Assimp reserves memory for the count before it reads
///   the values);
/// - an <accessor> that reaches past the end of its array (Assimp reads offset +
///   index * stride + component without a bound), names no array of the file, has more
///   <param>s than its stride, or, inside a <mesh>, reads a Name_array or IDREF_array
///   (Assimp reads their strings as numbers from an empty buffer);
/// - node graphs with cycles, nested too deep or expanding too far
///   (checkColladaNodeGraph).
void checkColladaForAssimp(const std::string& path, const std::string& file_text)
{
  const std::string text = withoutCommentsAndCdata(file_text);
  auto fail = [&](std::size_t at, const std::string& what) {
    throw FormatError(
        detail::where(path) + "line " +
        std::to_string(1 + std::count(text.begin(), text.begin() + at, '\n')) + ": " +
        what);
  };
  auto unsignedAttribute = [&](std::size_t at, std::string_view tag,
                               std::string_view name, std::uint64_t fallback,
                               const std::string& what) {
    std::string_view value;
    if (!attribute(tag, name, value))
      return fallback;
    std::uint64_t n = 0;
    const std::string_view v = trim(value);
    if (v.empty() ||
        std::from_chars(v.data(), v.data() + v.size(), n).ptr != v.data() + v.size())
      fail(at, what + " " + std::string(name) + " '" + std::string(value) +
                   "' is not a non-negative integer");
    return n;
  };

  struct Array {
    std::uint64_t count;
    bool numeric;
  };
  std::unordered_map<std::string, Array> arrays;
  static const char* const kArrays[] = {"float_array", "int_array", "bool_array",
                                        "Name_array", "IDREF_array"};
  constexpr std::uint64_t kNoCount = ~std::uint64_t{0};
  for (const char* name : kArrays)
    forEachStartTag(text, name, [&](std::size_t at, std::string_view tag) {
      const std::string what = "<" + std::string(name) + ">";
      const std::uint64_t n = unsignedAttribute(at, tag, "count", kNoCount, what);
      if (n == kNoCount)
        fail(at, what + " needs a count attribute holding a non-negative integer");
      // Each value takes at least one character and a separator.
      if (n > text.size() / 2 + 1)
        fail(at,
             what + " count " + std::to_string(n) + " is more than the file can hold");
      std::string_view id;
      if (attribute(tag, "id", id) &&
          !arrays.emplace(std::string(id), Array{n, name[0] != 'N' && name[0] != 'I'})
               .second)
        fail(at, what + " id '" + std::string(id) + "' is not unique");
    });

  std::vector<std::pair<std::size_t, std::size_t>> meshes; // [begin, end) of each <mesh>
  forEachStartTag(text, "mesh", [&](std::size_t at, std::string_view) {
    const std::size_t end = text.find("</mesh>", at);
    meshes.emplace_back(at, end == std::string::npos ? text.size() : end);
  });
  forEachStartTag(text, "accessor", [&](std::size_t at, std::string_view tag) {
    const std::string what = "<accessor>";
    const std::uint64_t count = unsignedAttribute(at, tag, "count", kNoCount, what);
    if (count == kNoCount)
      fail(at, what + " needs a count attribute");
    const std::uint64_t offset = unsignedAttribute(at, tag, "offset", 0, what);
    const std::uint64_t stride = unsignedAttribute(at, tag, "stride", 1, what);
    if (stride == 0)
      fail(at, what + " stride must be at least 1");
    std::string_view source;
    if (!attribute(tag, "source", source) || source.size() < 2 || source[0] != '#')
      fail(at, what + " needs a source attribute '#id' naming an array");
    const auto array = arrays.find(std::string(source.substr(1)));
    if (array == arrays.end())
      fail(at, what + " source '" + std::string(source) + "' names no array of the file");
    const Array& a = array->second;
    if (offset > a.count || count > (a.count - offset) / stride)
      fail(at, what + " reads " + std::to_string(count) + " x stride " +
                   std::to_string(stride) + " values from offset " +
                   std::to_string(offset) + " of '" + array->first + "', which holds " +
                   std::to_string(a.count));
    const std::size_t end = std::min(text.find("</accessor>", at), text.size());
    std::uint64_t params = 0;
    forEachStartTag(std::string_view(text).substr(at, end - at), "param",
                    [&](std::size_t, std::string_view) { ++params; });
    if (params > stride)
      fail(at, what + " has " + std::to_string(params) +
                   " <param>s, more than its stride " + std::to_string(stride));
    // <mesh> elements do not nest and are found in file order: the last one that starts
    // before the accessor is the only one that can hold it.
    const auto after =
        std::upper_bound(meshes.begin(), meshes.end(), at,
                         [](std::size_t a, const auto& m) { return a < m.first; });
    const bool in_mesh = after != meshes.begin() && at < std::prev(after)->second;
    if (in_mesh && !a.numeric)
      fail(at, what + " of a <mesh> reads '" + array->first +
                   "', which holds names, not numbers");
  });

  checkColladaNodeGraph(text, fail);

  static const char* const kIndexLists[] = {"p", "h", "v", "vcount"};
  for (const char* name : kIndexLists)
    forEachStartTag(text, name, [&](std::size_t at, std::string_view tag) {
      const std::size_t begin = at + tag.size() + 1;
      const std::size_t end = text.find('<', begin);
      const std::size_t bad = text.find_first_not_of("0123456789 \t\r\n", begin);
      if (bad < end && bad != std::string::npos)
        fail(bad, "<" + std::string(name) +
                      "> must hold non-negative integers only, found '" + text[bad] +
                      "'");
    });
}

/// A binary STL states its triangle count in its first 84 bytes: refuse a file over the
/// limit before Assimp allocates for it.
void checkStlTriangleCount(const std::string& path, const InputLimits& limits)
{
  if (limits.max_triangles == 0 && limits.max_points == 0)
    return;
  const std::uint64_t size = std::filesystem::file_size(path);
  if (size < 84)
    return;
  std::ifstream in(path, std::ios::binary);
  unsigned char header[84];
  if (!in.read(reinterpret_cast<char*>(header), 84))
    return;
  const std::uint64_t n = header[80] | (header[81] << 8) | (header[82] << 16) |
                          (std::uint64_t{header[83]} << 24);
  if (size == 84 + 50 * n) { // binary: 50 bytes per triangle, 3 vertices each
    detail::checkLimit(path, n, "triangles", limits.max_triangles, "max_triangles");
    detail::checkLimit(path, 3 * n, "vertices", limits.max_points, "max_points");
  }
}

Eigen::Matrix4d toEigen(const aiMatrix4x4& m)
{
  Eigen::Matrix4d e;
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c)
      e(r, c) = m[r][c];
  return e;
}

/// The name a triangle keeps: its node's, else the Collada id, else its mesh's.
std::string nameOf(const aiNode& node, const aiMesh& mesh)
{
  std::string name = node.mName.C_Str();
  // Assimp invents "$ColladaAutoName$_N" for a Collada node without a name attribute.
  if (!name.empty() && name.rfind("$ColladaAutoName$", 0) != 0)
    return name;
  aiString id;
  if (node.mMetaData && node.mMetaData->Get("Collada_id", id) && id.length > 0)
    return id.C_Str();
  return mesh.mName.C_Str();
}

class AssimpCollector {
public:
  explicit AssimpCollector(const aiScene& scene) : scene_(scene) {}

  /// Counts the triangles and vertices of the node tree (instances counted each time),
  /// as collect() copies them.
  void count(const aiNode& node, std::uint64_t& triangles, std::uint64_t& vertices) const
  {
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh& m = *scene_.mMeshes[node.mMeshes[i]];
      if (!(m.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)))
        continue;
      vertices += m.mNumVertices;
      for (unsigned f = 0; f < m.mNumFaces; ++f)
        triangles += m.mFaces[f].mNumIndices == 3;
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
      count(*node.mChildren[c], triangles, vertices);
  }

  /// Appends the triangles of the node and its descendants, placed by their transforms
  /// (the node's own one only if use_own_transform).
  void collect(const aiNode& node, const Eigen::Matrix4d& parent, TriangleMesh& out,
               bool use_own_transform = true)
  {
    const Eigen::Matrix4d global =
        use_own_transform ? Eigen::Matrix4d(parent * toEigen(node.mTransformation))
                          : parent;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh& m = *scene_.mMeshes[node.mMeshes[i]];
      if (!(m.mPrimitiveTypes & (aiPrimitiveType_TRIANGLE | aiPrimitiveType_POLYGON)))
        continue; // points and lines only
      const std::uint32_t id =
          ids_.idOf({nameOf(node, m), m.mName.C_Str(), materialName(m)}, out);
      const auto base = static_cast<std::uint32_t>(out.vertices.size());
      for (unsigned v = 0; v < m.mNumVertices; ++v) {
        const aiVector3D& p = m.mVertices[v];
        const Eigen::Vector4d q = global * Eigen::Vector4d(p.x, p.y, p.z, 1.0);
        out.vertices.push_back(q.head<3>().cast<float>());
      }
      for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3)
          continue;
        out.triangles.push_back(
            {base + face.mIndices[0], base + face.mIndices[1], base + face.mIndices[2]});
        out.node_ids.push_back(id);
      }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
      collect(*node.mChildren[c], global, out);
  }

private:
  /// The material's name; "" for none or Assimp's own default material.
  std::string materialName(const aiMesh& m) const
  {
    aiString name;
    if (m.mMaterialIndex >= scene_.mNumMaterials ||
        scene_.mMaterials[m.mMaterialIndex]->Get(AI_MATKEY_NAME, name) != AI_SUCCESS ||
        std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME)
      return "";
    return name.C_Str();
  }

  const aiScene& scene_;
  detail::MeshNameIds ids_;
};

/// OBJ, STL and Collada through Assimp, in file axes; for Collada in file units too.
///
/// Assimp 5.2.5 (Debian 12) puts Collada's <unit> scale into the root node's transform
/// and, unless AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION is set, also a rotation that
/// takes Z_UP (or X_UP) files to Y up; it sets no "UnitScaleFactor" metadata. The
/// root node is Collada's <visual_scene>, which has no transform of its own, so we
/// drop the root transform and apply the unit and up axis ourselves: exactly once,
/// whatever the Assimp version does.
TriangleMesh readWithAssimp(const std::string& path, const std::string& ext,
                            const InputLimits& limits)
{
  if (ext == ".stl")
    checkStlTriangleCount(path, limits);
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  // Node names from Collada's `name` attributes (what modelling tools show), not ids.
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_USE_COLLADA_NAMES, true);
  // Without normals and texture coordinates, JoinIdenticalVertices merges by position.
  importer.SetPropertyInteger(AI_CONFIG_PP_RVC_FLAGS,
                              aiComponent_NORMALS | aiComponent_TANGENTS_AND_BITANGENTS |
                                  aiComponent_COLORS | aiComponent_TEXCOORDS |
                                  aiComponent_BONEWEIGHTS);
  // Not PreTransformVertices: it merges meshes and loses the node names.
  const unsigned flags = aiProcess_Triangulate | aiProcess_JoinIdenticalVertices |
                         aiProcess_RemoveComponent | aiProcess_ValidateDataStructure;
  const aiScene* scene = importer.ReadFile(path, flags);
  if (!scene || !scene->mRootNode)
    throw FormatError(detail::where(path) + "cannot be read as " + ext.substr(1) + ": " +
                      importer.GetErrorString());
  AssimpCollector collector(*scene);
  std::uint64_t triangles = 0, vertices = 0;
  collector.count(*scene->mRootNode, triangles, vertices);
  detail::checkLimit(path, triangles, "triangles", limits.max_triangles, "max_triangles");
  detail::checkLimit(path, vertices, "vertices", limits.max_points, "max_points");
  TriangleMesh mesh;
  mesh.vertices.reserve(static_cast<std::size_t>(vertices));
  mesh.triangles.reserve(static_cast<std::size_t>(triangles));
  mesh.node_ids.reserve(static_cast<std::size_t>(triangles));
  const aiNode& root = *scene->mRootNode;
  // The Collada root is the <visual_scene>: its transform is Assimp's unit scale only.
  collector.collect(root, Eigen::Matrix4d::Identity(), mesh, ext != ".dae");
  return mesh;
}

} // namespace

void checkColladaText(const std::string& path, const std::string& text)
{
  checkColladaForAssimp(path, text);
}

MeshLoadOptions::UpAxis upAxisFromName(const std::string& name)
{
  for (const auto axis : {MeshLoadOptions::UpAxis::from_file, MeshLoadOptions::UpAxis::y,
                          MeshLoadOptions::UpAxis::z})
    if (name == upAxisName(axis))
      return axis;
  throw InvalidArgumentError("up axis: expected 'file', 'y' or 'z', got '" + name + "'");
}

const char* upAxisName(MeshLoadOptions::UpAxis axis)
{
  switch (axis) {
  case MeshLoadOptions::UpAxis::y:
    return "y";
  case MeshLoadOptions::UpAxis::z:
    return "z";
  case MeshLoadOptions::UpAxis::from_file:
    break;
  }
  return "file";
}

Eigen::Matrix3d upAxisRotation(MeshLoadOptions::UpAxis axis)
{
  return detail::upToZ(axis == MeshLoadOptions::UpAxis::y ? detail::Up::y
                                                          : detail::Up::z);
}

TriangleMesh loadMesh(const std::string& path, const MeshLoadOptions& options,
                      MeshFileUnits* units)
{
  if (!std::isfinite(options.scale) || options.scale < 0.0)
    throw InvalidArgumentError(
        "MeshLoadOptions::scale must be a finite number >= 0 (0 = from "
        "the file), got " +
        std::to_string(options.scale));
  const std::string ext = extensionOf(path);
  const bool ply = ext == ".ply", vrml = ext == ".wrl" || ext == ".vrml";
  const bool assimp = ext == ".obj" || ext == ".stl" || ext == ".dae";
  if (!ply && !vrml && !assimp)
    throw FormatError(detail::where(path) + "unknown mesh extension '" + ext + "' (" +
                      kMeshExtensions + ")");
  const InputLimits& limits = options.limits;
  requireRegularFile(path);
  detail::checkFileSize(path, limits);

  // The file's own conventions: Collada says them, VRML is Y up, the rest Z up in metres.
  ColladaAsset file;
  file.up = vrml ? detail::Up::y : detail::Up::z;
  if (ext == ".dae") {
    const std::string text = detail::readFileToString(path, limits);
    file = scanColladaAsset(path, text);
    checkColladaForAssimp(path, text);
  }
  TriangleMesh mesh = ply    ? detail::readPlyMesh(path, limits)
                      : vrml ? detail::readVrml(path, limits)
                             : readWithAssimp(path, ext, limits);
  if (mesh.triangles.empty())
    throw FormatError(
        detail::where(path) + "no triangles" +
        (ply ? " (a PLY without faces is a point cloud: use loadCloud)" : ""));

  const detail::Up up = options.up_axis == MeshLoadOptions::UpAxis::from_file ? file.up
                        : options.up_axis == MeshLoadOptions::UpAxis::y ? detail::Up::y
                                                                        : detail::Up::z;
  const double scale = options.scale > 0.0 ? options.scale : file.meter;
  if (units) {
    units->can_declare_unit = ext == ".dae";
    units->unit_declared = file.has_unit;
    units->metres_per_unit = scale;
  }
  if (up != detail::Up::z || scale != 1.0) {
    const Eigen::Matrix3d m = scale * detail::upToZ(up);
    for (auto& v : mesh.vertices)
      v = (m * v.cast<double>()).cast<float>();
  }
  try {
    mesh.validate();
  } catch (const FormatError& e) {
    throw FormatError(detail::where(path) + e.what());
  }
  return mesh;
}

} // namespace io
} // namespace plantnbv
