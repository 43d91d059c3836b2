// A VRML97 (VRML 2.0) reader for the geometry of a scene.
//
// Why not VTK's vtkVRMLImporter: in VTK 9.1 (Debian 12) it ignores Transform `rotation`,
// `center` and `scaleOrientation` and composes `translation` and `scale` in the order
// they appear in the file (checked with a probe: a triangle under `rotation 0 0 1 1.57`
// came out unrotated), so plant models placed by rotated Transforms came out wrong. It
// also keeps its parser state in globals (not thread-safe) and needs a renderer.
//
// Supported: Transform (the full VRML97 matrix T C R SR S -SR -C), Group, Collision,
// Anchor, Billboard (as a Group), Switch (the chosen child), LOD (the first level),
// Shape with IndexedFaceSet (polygons cut to their true area, `ccw` honoured), Box,
// Cylinder, Cone and Sphere; DEF/USE. Skipped: points, lines, Text, ElevationGrid,
// Extrusion, Inline (external files) and instances of PROTOs (not expanded).

#include <array>
#include <charconv>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <string_view>
#include <unordered_map>
#include <vector>

#include <Eigen/Geometry>

#include <plantnbv/common/error.h>
#include <plantnbv/common/number_text.h>

#include "io_util.h"
#include "polygon_triangulation.h"

namespace plantnbv {
namespace io {

namespace {

struct Token {
  enum Kind {
    end,
    open_brace,
    close_brace,
    open_bracket,
    close_bracket,
    string,
    number,
    word
  };
  Kind kind = end;
  std::string_view text;
  double value = 0.0;
  std::size_t line = 0;
};

class Lexer {
public:
  Lexer(const std::string& path, const std::string& text) : path_(path), text_(text)
  {
    advance();
  }

  const Token& peek() const { return next_; }
  Token take()
  {
    Token t = next_;
    advance();
    return t;
  }

  FormatError error(std::size_t line, const std::string& what) const
  {
    return FormatError(detail::where(path_) + "line " + std::to_string(line) + ": " +
                       what);
  }

private:
  void advance()
  {
    const std::size_t n = text_.size();
    // Whitespace, commas (whitespace in VRML) and # comments.
    while (pos_ < n) {
      const char c = text_[pos_];
      if (c == '\n')
        ++line_;
      if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',')
        ++pos_;
      else if (c == '#')
        while (pos_ < n && text_[pos_] != '\n')
          ++pos_;
      else
        break;
    }
    next_ = Token{};
    next_.line = line_;
    if (pos_ >= n)
      return;
    const char c = text_[pos_];
    const std::size_t start = pos_;
    switch (c) {
    case '{':
      next_.kind = Token::open_brace;
      break;
    case '}':
      next_.kind = Token::close_brace;
      break;
    case '[':
      next_.kind = Token::open_bracket;
      break;
    case ']':
      next_.kind = Token::close_bracket;
      break;
    case '"': {
      ++pos_;
      while (pos_ < n && text_[pos_] != '"') {
        if (text_[pos_] == '\\')
          ++pos_;
        else if (text_[pos_] == '\n')
          ++line_;
        ++pos_;
      }
      if (pos_ >= n)
        throw error(next_.line, "unterminated string");
      next_.kind = Token::string;
      next_.text = std::string_view(text_).substr(start, pos_ + 1 - start);
      ++pos_;
      return;
    }
    default:
      while (pos_ < n && !isDelimiter(text_[pos_]))
        ++pos_;
      next_.text = std::string_view(text_).substr(start, pos_ - start);
      next_.kind = isNumberStart(c) ? Token::number : Token::word;
      if (next_.kind == Token::number)
        next_.value = parseNumber(next_.text, next_.line);
      return;
    }
    next_.text = std::string_view(text_).substr(start, 1);
    ++pos_;
  }

  static bool isDelimiter(char c)
  {
    return c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == ',' || c == '{' ||
           c == '}' || c == '[' || c == ']' || c == '"' || c == '#';
  }
  static bool isNumberStart(char c)
  {
    return (c >= '0' && c <= '9') || c == '-' || c == '+' || c == '.';
  }

  double parseNumber(std::string_view s, std::size_t line) const
  {
    std::string_view body = s;
    bool negative = false;
    if (!body.empty() && (body[0] == '+' || body[0] == '-')) {
      negative = body[0] == '-';
      body.remove_prefix(1);
    }
    double v = 0.0;
    std::from_chars_result r{};
    if (body.size() > 2 && body[0] == '0' && (body[1] == 'x' || body[1] == 'X')) {
      // SFInt32 may be written in hexadecimal.
      std::uint64_t u = 0;
      r = std::from_chars(body.data() + 2, body.data() + body.size(), u, 16);
      v = static_cast<double>(u);
    } else
      r = std::from_chars(body.data(), body.data() + body.size(), v);
    if (body.empty() || r.ec != std::errc() || r.ptr != body.data() + body.size())
      throw error(line, "'" + std::string(s) + "' is not a number");
    return negative ? -v : v;
  }

  const std::string& path_;
  const std::string& text_;
  std::size_t pos_ = 0;
  std::size_t line_ = 1;
  Token next_;
};

struct Node;
using NodePtr = std::shared_ptr<const Node>;

/// A field value, whatever its type: numbers (booleans as 0/1) and nodes.
struct Field {
  std::vector<double> numbers;
  std::vector<NodePtr> nodes;
  std::size_t line = 0;
};

struct Node {
  std::string type;
  std::string def;
  std::size_t line = 0;
  std::map<std::string, Field, std::less<>> fields;

  const Field* field(std::string_view name) const
  {
    const auto it = fields.find(name);
    return it == fields.end() ? nullptr : &it->second;
  }
};

/// Parses the file into a tree of generic nodes; it needs no knowledge of field types.
class Parser {
public:
  Parser(const std::string& path, const std::string& text) : lex_(path, text) {}

  std::vector<NodePtr> parseScene()
  {
    std::vector<NodePtr> roots;
    while (lex_.peek().kind != Token::end)
      if (NodePtr n = parseStatement(0))
        roots.push_back(std::move(n));
    return roots;
  }

private:
  static constexpr int kMaxDepth = 1000;

  std::string expectWord(const std::string& what)
  {
    const Token t = lex_.take();
    if (t.kind != Token::word)
      throw lex_.error(
          t.line, std::string("expected ") + what + ", got '" +
                      (t.kind == Token::end ? "end of file" : std::string(t.text)) + "'");
    return std::string(t.text);
  }

  /// Skips one balanced [...] or {...} group, or a single token.
  void skipGroup()
  {
    int depth = 0;
    do {
      const Token t = lex_.take();
      if (t.kind == Token::end)
        throw lex_.error(t.line, "unexpected end of file");
      if (t.kind == Token::open_brace || t.kind == Token::open_bracket)
        ++depth;
      else if (t.kind == Token::close_brace || t.kind == Token::close_bracket)
        --depth;
    } while (depth > 0);
  }

  /// PROTO, EXTERNPROTO and ROUTE statements carry no geometry of their own.
  bool skipDeclaration(const std::string_view word)
  {
    if (word == "PROTO") {
      lex_.take();
      expectWord("a PROTO name");
      skipGroup(); // interface
      skipGroup(); // body
      return true;
    }
    if (word == "EXTERNPROTO") {
      lex_.take();
      expectWord("an EXTERNPROTO name");
      skipGroup(); // interface
      skipGroup(); // URL: a string or a list of strings
      return true;
    }
    if (word == "ROUTE") {
      lex_.take();
      expectWord("a ROUTE source");
      expectWord("TO");
      expectWord("a ROUTE destination");
      return true;
    }
    return false;
  }

  /// A node, DEF name node, USE name or NULL (returns nullptr) at top level or in a
  /// value.
  NodePtr parseStatement(int depth)
  {
    const Token t = lex_.peek();
    if (t.kind != Token::word)
      throw lex_.error(
          t.line, "expected a node, got '" +
                      (t.kind == Token::end ? "end of file" : std::string(t.text)) + "'");
    if (skipDeclaration(t.text))
      return nullptr;
    return parseNodeValue(depth);
  }

  NodePtr parseNodeValue(int depth)
  {
    const Token t = lex_.take();
    if (t.text == "NULL")
      return nullptr;
    if (t.text == "USE") {
      const std::string name = expectWord("a DEF name after USE");
      const auto it = defs_.find(name);
      if (it == defs_.end())
        throw lex_.error(t.line, "USE of undefined name '" + name + "'");
      return it->second;
    }
    std::string def;
    std::string type(t.text);
    if (t.text == "DEF") {
      def = expectWord("a name after DEF");
      type = expectWord("a node type after DEF " + def);
    }
    NodePtr node = parseNodeBody(type, def, t.line, depth);
    // Registered once complete, so a node cannot USE itself (no cycles).
    if (!def.empty())
      defs_[def] = node;
    return node;
  }

  NodePtr parseNodeBody(const std::string& type, const std::string& def, std::size_t line,
                        int depth)
  {
    if (depth > kMaxDepth)
      throw lex_.error(line, "nodes nested deeper than " + std::to_string(kMaxDepth));
    auto node = std::make_shared<Node>();
    node->type = type;
    node->def = def;
    node->line = line;
    const Token open = lex_.take();
    if (open.kind != Token::open_brace)
      throw lex_.error(open.line, "expected '{' after node type '" + type + "'");
    while (lex_.peek().kind != Token::close_brace) {
      const Token t = lex_.peek();
      if (t.kind == Token::end)
        throw lex_.error(line, "node '" + type + "' is not closed");
      if (t.kind != Token::word)
        throw lex_.error(t.line, "expected a field name in node '" + type + "', got '" +
                                     std::string(t.text) + "'");
      if (skipDeclaration(t.text))
        continue;
      lex_.take();
      if (t.text == "field" || t.text == "exposedField" || t.text == "eventIn" ||
          t.text == "eventOut") {
        // Script interface declarations: type and name, then a value for fields.
        expectWord("a field type");
        expectWord("a field name");
        if (t.text == "field" || t.text == "exposedField") {
          Field ignored;
          parseFieldValue(ignored, depth);
        }
        continue;
      }
      Field& f = node->fields[std::string(t.text)];
      f = Field{};
      f.line = t.line;
      parseFieldValue(f, depth);
    }
    lex_.take();
    return node;
  }

  void parseFieldValue(Field& f, int depth)
  {
    const Token t = lex_.peek();
    switch (t.kind) {
    case Token::number:
      while (lex_.peek().kind == Token::number)
        f.numbers.push_back(lex_.take().value);
      return;
    case Token::string:
      lex_.take();
      return;
    case Token::open_bracket:
      lex_.take();
      while (lex_.peek().kind != Token::close_bracket) {
        const Token item = lex_.peek();
        if (item.kind == Token::number)
          f.numbers.push_back(lex_.take().value);
        else if (item.kind == Token::string)
          lex_.take();
        else if (item.kind == Token::word &&
                 (item.text == "TRUE" || item.text == "FALSE"))
          f.numbers.push_back(lex_.take().text == "TRUE" ? 1.0 : 0.0);
        else if (item.kind == Token::word) {
          if (NodePtr n = parseNodeValue(depth + 1))
            f.nodes.push_back(std::move(n));
        } else
          throw lex_.error(
              item.line,
              "unexpected '" +
                  (item.kind == Token::end ? "end of file" : std::string(item.text)) +
                  "' in a list");
      }
      lex_.take();
      return;
    case Token::word:
      if (t.text == "TRUE" || t.text == "FALSE") {
        f.numbers.push_back(lex_.take().text == "TRUE" ? 1.0 : 0.0);
        return;
      }
      if (t.text == "IS") { // inside PROTO bodies only, which are skipped; tolerated
        lex_.take();
        expectWord("a PROTO field name after IS");
        return;
      }
      if (NodePtr n = parseNodeValue(depth + 1))
        f.nodes.push_back(std::move(n));
      return;
    default:
      throw lex_.error(
          t.line, "expected a field value, got '" +
                      (t.kind == Token::end ? "end of file" : std::string(t.text)) + "'");
    }
  }

  Lexer lex_;
  std::unordered_map<std::string, NodePtr> defs_;
};

const std::set<std::string, std::less<>>& standardNodeTypes()
{
  static const std::set<std::string, std::less<>> kTypes = {"Anchor",
                                                            "Appearance",
                                                            "AudioClip",
                                                            "Background",
                                                            "Billboard",
                                                            "Box",
                                                            "Collision",
                                                            "Color",
                                                            "ColorInterpolator",
                                                            "Cone",
                                                            "Coordinate",
                                                            "CoordinateInterpolator",
                                                            "Cylinder",
                                                            "CylinderSensor",
                                                            "DirectionalLight",
                                                            "ElevationGrid",
                                                            "Extrusion",
                                                            "Fog",
                                                            "FontStyle",
                                                            "Group",
                                                            "ImageTexture",
                                                            "IndexedFaceSet",
                                                            "IndexedLineSet",
                                                            "Inline",
                                                            "LOD",
                                                            "Material",
                                                            "MovieTexture",
                                                            "NavigationInfo",
                                                            "Normal",
                                                            "NormalInterpolator",
                                                            "OrientationInterpolator",
                                                            "PixelTexture",
                                                            "PlaneSensor",
                                                            "PointLight",
                                                            "PointSet",
                                                            "PositionInterpolator",
                                                            "ProximitySensor",
                                                            "ScalarInterpolator",
                                                            "Script",
                                                            "Shape",
                                                            "Sound",
                                                            "Sphere",
                                                            "SphereSensor",
                                                            "SpotLight",
                                                            "Switch",
                                                            "Text",
                                                            "TextureCoordinate",
                                                            "TextureTransform",
                                                            "TimeSensor",
                                                            "TouchSensor",
                                                            "Transform",
                                                            "Viewpoint",
                                                            "VisibilitySensor",
                                                            "WorldInfo"};
  return kTypes;
}

/// Turns the node tree into triangles in file coordinates.
class SceneBuilder {
public:
  SceneBuilder(const std::string& path, const InputLimits& limits)
      : path_(path), limits_(limits)
  {
  }

  void walk(const Node& n, const Eigen::Affine3d& M, const std::string& name)
  {
    // DEF/USE makes a DAG: nested USEs of groups can multiply to 2^depth instances,
    // with or without geometry. A real scene has fewer node instances than triangles.
    const std::uint64_t max = limits_.max_triangles;
    if (max > 0 && ++instances_ > max)
      throw FormatError(detail::where(path_) + "more than " + std::to_string(max) +
                        " node instances, DEF/USE nested too often (the limit, "
                        "InputLimits::max_triangles)");
    const std::string& here = n.def.empty() ? name : n.def;
    if (n.type == "Transform")
      walkChildren(n, "children", M * transformOf(n), here);
    else if (n.type == "Group" || n.type == "Collision" || n.type == "Anchor" ||
             n.type == "Billboard")
      walkChildren(n, "children", M, here);
    else if (n.type == "Switch") {
      const Field* which = n.field("whichChoice");
      const Field* choice = n.field("choice");
      if (which && choice && which->numbers.size() == 1 && which->numbers[0] >= 0 &&
          which->numbers[0] < static_cast<double>(choice->nodes.size()))
        walk(*choice->nodes[static_cast<std::size_t>(which->numbers[0])], M, here);
    } else if (n.type == "LOD") {
      const Field* level = n.field("level");
      if (level && !level->nodes.empty())
        walk(*level->nodes.front(), M, here);
    } else if (n.type == "Shape") {
      const Field* geometry = n.field("geometry");
      ++shapes_;
      if (geometry && !geometry->nodes.empty())
        addGeometry(*geometry->nodes.front(), M, here, materialName(n));
    } else if (n.type == "Inline")
      skipped_.insert("Inline");
    else if (!standardNodeTypes().count(n.type))
      skipped_.insert(n.type + " (PROTO instance)");
  }

  TriangleMesh& mesh() { return mesh_; }
  const std::set<std::string>& skipped() const { return skipped_; }

private:
  void walkChildren(const Node& n, const char* field, const Eigen::Affine3d& M,
                    const std::string& name)
  {
    if (const Field* children = n.field(field))
      for (const auto& child : children->nodes)
        walk(*child, M, name);
  }

  /// `count` numbers of field `name`, or `defaults` when the field is absent.
  std::vector<double> numbers(const Node& n, const char* name,
                              std::vector<double> defaults)
  {
    const Field* f = n.field(name);
    if (!f)
      return defaults;
    if (f->numbers.size() != defaults.size())
      throw FormatError(detail::where(path_) + "line " + std::to_string(f->line) + ": " +
                        n.type + " field '" + name + "' needs " +
                        std::to_string(defaults.size()) + " numbers, got " +
                        std::to_string(f->numbers.size()));
    return f->numbers;
  }

  static Eigen::AngleAxisd rotation(const std::vector<double>& r)
  {
    const Eigen::Vector3d axis(r[0], r[1], r[2]);
    // A zero axis means no rotation (some exporters write 0 0 0 0).
    if (axis.norm() == 0.0)
      return Eigen::AngleAxisd(0.0, Eigen::Vector3d::UnitZ());
    return Eigen::AngleAxisd(r[3], axis.normalized());
  }

  /// VRML97 Transform: P' = T * C * R * SR * S * SR^-1 * C^-1 * P.
  Eigen::Affine3d transformOf(const Node& n)
  {
    const auto t = numbers(n, "translation", {0, 0, 0});
    const auto c = numbers(n, "center", {0, 0, 0});
    const auto r = numbers(n, "rotation", {0, 0, 1, 0});
    const auto s = numbers(n, "scale", {1, 1, 1});
    const auto sr = numbers(n, "scaleOrientation", {0, 0, 1, 0});
    const Eigen::Vector3d C(c[0], c[1], c[2]);
    const Eigen::AngleAxisd SR = rotation(sr);
    Eigen::Affine3d m = Eigen::Affine3d::Identity();
    m.translate(Eigen::Vector3d(t[0], t[1], t[2]))
        .translate(C)
        .rotate(rotation(r))
        .rotate(SR)
        .scale(Eigen::Vector3d(s[0], s[1], s[2]))
        .rotate(SR.inverse())
        .translate(-C);
    return m;
  }

  /// The DEF name of a Shape's Material, else of its Appearance, else "".
  static std::string materialName(const Node& shape)
  {
    const Field* appearance = shape.field("appearance");
    if (!appearance || appearance->nodes.empty())
      return "";
    const Node& a = *appearance->nodes.front();
    const Field* material = a.field("material");
    if (material && !material->nodes.empty() && !material->nodes.front()->def.empty())
      return material->nodes.front()->def;
    return a.def;
  }

  void addTriangle(std::uint32_t a, std::uint32_t b, std::uint32_t c, std::uint32_t node)
  {
    const std::uint64_t max = limits_.max_triangles;
    if (max > 0 && mesh_.triangles.size() >= max)
      throw FormatError(detail::where(path_) + "more than " + std::to_string(max) +
                        " triangles (the limit, InputLimits::max_triangles)");
    if (flip_)
      std::swap(b, c);
    mesh_.triangles.push_back({a, b, c});
    mesh_.node_ids.push_back(node);
  }

  std::uint32_t addVertex(const Eigen::Affine3d& M, const Eigen::Vector3d& p)
  {
    if (mesh_.vertices.size() >= std::numeric_limits<std::uint32_t>::max())
      throw FormatError(detail::where(path_) + "more than 2^32 - 1 vertices");
    const std::uint64_t max = limits_.max_points;
    if (max > 0 && mesh_.vertices.size() >= max)
      throw FormatError(detail::where(path_) + "more than " + std::to_string(max) +
                        " vertices (the limit, InputLimits::max_points)");
    mesh_.vertices.push_back((M * p).cast<float>());
    return static_cast<std::uint32_t>(mesh_.vertices.size() - 1);
  }

  void addGeometry(const Node& g, const Eigen::Affine3d& M, const std::string& name,
                   const std::string& material)
  {
    const std::string node_name = !g.def.empty() ? g.def
                                  : !name.empty()
                                      ? name
                                      : "shape_" + std::to_string(shapes_ - 1);
    const std::uint32_t id = ids_.idOf({node_name, g.def, material}, mesh_);
    // A mirroring transform turns the faces inside out; swapping two corners undoes it.
    flip_ = M.linear().determinant() < 0.0;
    if (g.type == "IndexedFaceSet")
      addFaceSet(g, M, id);
    else if (g.type == "Box")
      addBox(g, M, id);
    else if (g.type == "Cylinder" || g.type == "Cone")
      addRevolved(g, M, id);
    else if (g.type == "Sphere")
      addSphere(g, M, id);
    else
      skipped_.insert(g.type);
  }

  void addFaceSet(const Node& g, const Eigen::Affine3d& M, std::uint32_t id)
  {
    const Field* coord = g.field("coord");
    const Field* index = g.field("coordIndex");
    if (!coord || coord->nodes.empty() || !index)
      return; // an empty face set is legal VRML
    const Node& c = *coord->nodes.front();
    const Field* point = c.field("point");
    if (!point)
      return;
    if (point->numbers.size() % 3 != 0)
      throw FormatError(detail::where(path_) + "line " + std::to_string(point->line) +
                        ": Coordinate point holds " +
                        std::to_string(point->numbers.size()) +
                        " numbers, not a multiple of 3");
    const std::size_t count = point->numbers.size() / 3;
    const auto base = static_cast<std::uint32_t>(mesh_.vertices.size());
    for (std::size_t i = 0; i < count; ++i) {
      const double* p = &point->numbers[3 * i];
      addVertex(M, Eigen::Vector3d(p[0], p[1], p[2]));
    }
    const Field* ccw_field = g.field("ccw");
    const bool ccw =
        !ccw_field || ccw_field->numbers.empty() || ccw_field->numbers[0] != 0.0;
    if (!ccw)
      flip_ = !flip_;
    // A polygon is cut at its end (-1 or the last index): a fan for a convex one, ear
    // clipping otherwise, so that every face gets its true area.
    std::vector<std::uint32_t> corners;
    std::vector<std::array<std::uint32_t, 3>> cut;
    const auto endPolygon = [&] {
      cut.clear();
      const detail::PolygonCut done = detail::triangulatePolygon(
          mesh_.vertices, corners, cut, ear_clipping_steps_left_);
      if (done != detail::PolygonCut::cut)
        throw FormatError(detail::where(path_) + "line " + std::to_string(index->line) +
                          ": " + detail::untriangulableFace(done, corners.size()));
      for (const auto& t : cut)
        addTriangle(t[0], t[1], t[2], id);
      corners.clear();
    };
    for (double v : index->numbers) {
      if (v == -1.0) {
        endPolygon();
        continue;
      }
      if (v < 0 || v >= static_cast<double>(count) || v != std::floor(v))
        throw FormatError(detail::where(path_) + "line " + std::to_string(index->line) +
                          ": coordIndex " + shortestText(v) + " is out of range (" +
                          std::to_string(count) + " points)");
      const std::uint64_t max = limits_.max_triangles;
      if (max > 0 && corners.size() > max + 2)
        throw FormatError(detail::where(path_) + "more than " + std::to_string(max) +
                          " triangles (the limit, InputLimits::max_triangles)");
      corners.push_back(base + static_cast<std::uint32_t>(v));
    }
    endPolygon();
  }

  void addBox(const Node& g, const Eigen::Affine3d& M, std::uint32_t id)
  {
    const auto s = numbers(g, "size", {2, 2, 2});
    const auto base = static_cast<std::uint32_t>(mesh_.vertices.size());
    for (int i = 0; i < 8; ++i)
      addVertex(M,
                Eigen::Vector3d((i & 1 ? 0.5 : -0.5) * s[0], (i & 2 ? 0.5 : -0.5) * s[1],
                                (i & 4 ? 0.5 : -0.5) * s[2]));
    // Corner i has x from bit 0, y from bit 1, z from bit 2; faces wound outward.
    static const std::uint32_t kFaces[6][4] = {{0, 4, 6, 2}, {1, 3, 7, 5}, {0, 1, 5, 4},
                                               {2, 6, 7, 3}, {0, 2, 3, 1}, {4, 5, 7, 6}};
    for (const auto& f : kFaces) {
      addTriangle(base + f[0], base + f[1], base + f[2], id);
      addTriangle(base + f[0], base + f[2], base + f[3], id);
    }
  }

  /// Cylinder or Cone around +Y, centred at the origin (VRML97 defaults).
  void addRevolved(const Node& g, const Eigen::Affine3d& M, std::uint32_t id)
  {
    constexpr int kSegments = 32;
    const bool cone = g.type == "Cone";
    const double h = numbers(g, "height", {2})[0];
    const double r = numbers(g, cone ? "bottomRadius" : "radius", {1})[0];
    const double top_r = cone ? 0.0 : r;
    auto flag = [&](const char* name) { return numbers(g, name, {1})[0] != 0.0; };
    const bool side = flag("side"), bottom = flag("bottom"), top = !cone && flag("top");
    const auto base = static_cast<std::uint32_t>(mesh_.vertices.size());
    for (int k = 0; k < kSegments; ++k) {
      const double a = 2.0 * M_PI * k / kSegments;
      addVertex(M, Eigen::Vector3d(r * std::sin(a), -0.5 * h, r * std::cos(a)));
      addVertex(M, Eigen::Vector3d(top_r * std::sin(a), 0.5 * h, top_r * std::cos(a)));
    }
    const std::uint32_t bottom_centre = addVertex(M, Eigen::Vector3d(0, -0.5 * h, 0));
    const std::uint32_t top_centre = addVertex(M, Eigen::Vector3d(0, 0.5 * h, 0));
    for (std::uint32_t k = 0; k < kSegments; ++k) {
      const std::uint32_t k1 = (k + 1) % kSegments;
      const std::uint32_t b0 = base + 2 * k, t0 = b0 + 1, b1 = base + 2 * k1, t1 = b1 + 1;
      if (side) {
        addTriangle(b0, b1, t1, id);
        if (!cone)
          addTriangle(b0, t1, t0, id);
      }
      if (bottom)
        addTriangle(bottom_centre, b1, b0, id);
      if (top)
        addTriangle(top_centre, t0, t1, id);
    }
  }

  void addSphere(const Node& g, const Eigen::Affine3d& M, std::uint32_t id)
  {
    constexpr int kStacks = 16, kSlices = 32;
    const double r = numbers(g, "radius", {1})[0];
    const auto base = static_cast<std::uint32_t>(mesh_.vertices.size());
    for (int i = 0; i <= kStacks; ++i) {
      const double phi = M_PI * i / kStacks;
      for (int k = 0; k < kSlices; ++k) {
        const double a = 2.0 * M_PI * k / kSlices;
        addVertex(M, r * Eigen::Vector3d(std::sin(phi) * std::sin(a), std::cos(phi),
                                         std::sin(phi) * std::cos(a)));
      }
    }
    for (std::uint32_t i = 0; i < kStacks; ++i)
      for (std::uint32_t k = 0; k < kSlices; ++k) {
        const std::uint32_t k1 = (k + 1) % kSlices;
        const std::uint32_t a = base + i * kSlices + k, b = base + i * kSlices + k1;
        const std::uint32_t c = a + kSlices, d = b + kSlices;
        if (i > 0)
          addTriangle(a, c, b, id);
        if (i + 1 < kStacks)
          addTriangle(b, c, d, id);
      }
  }

  const std::string& path_;
  InputLimits limits_;
  std::uint64_t ear_clipping_steps_left_ = detail::kEarClippingStepsPerFile;
  std::uint64_t instances_ = 0;
  TriangleMesh mesh_;
  detail::MeshNameIds ids_;
  std::set<std::string> skipped_;
  std::size_t shapes_ = 0;
  bool flip_ = false;
};

} // namespace

namespace detail {

TriangleMesh readVrml(const std::string& path, const InputLimits& limits)
{
  const std::string text = readFileToString(path, limits);
  const std::string_view head = std::string_view(text).substr(0, text.find('\n'));
  if (head.rfind("#VRML V1.0", 0) == 0)
    throw FormatError(where(path) +
                      "VRML 1.0 is not supported (only VRML97, '#VRML V2.0')");
  if (head.rfind("#VRML V2.0", 0) != 0)
    throw FormatError(where(path) +
                      "not a VRML97 file (expected the header '#VRML V2.0 utf8')");
  Parser parser(path, text);
  const std::vector<NodePtr> roots = parser.parseScene();
  SceneBuilder builder(path, limits);
  for (const auto& root : roots)
    builder.walk(*root, Eigen::Affine3d::Identity(), "");
  TriangleMesh mesh = std::move(builder.mesh());
  if (mesh.triangles.empty()) {
    std::string what = where(path) + "no triangles";
    if (!builder.skipped().empty()) {
      what += " (skipped:";
      for (const auto& s : builder.skipped())
        what += " " + s;
      what += ")";
    }
    throw FormatError(what);
  }
  return mesh;
}

} // namespace detail
} // namespace io
} // namespace plantnbv
