#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <limits>
#include <omp.h>
#include <sstream>
#include <vector>

#include <octomap/AbstractOcTree.h>
#include <octomap/OcTree.h>
#include <pcl/common/point_tests.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/common/error.h>
#include <plantnbv/common/file_io.h>
#include <plantnbv/common/voxel_lattice.h>
#include <plantnbv/octree/octree_conversion.h>

namespace plantnbv {

namespace {

/// The first lines OctoMap writes (AbstractOccupancyOcTree::writeBinary,
/// AbstractOcTree::write); its readers check them too.
constexpr const char* kBinaryHeader = "# Octomap OcTree binary file";
constexpr const char* kFullHeader = "# Octomap OcTree file";

std::string lowerExtension(const std::string& path)
{
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

bool startsWith(const std::string& s, const char* prefix)
{
  return s.rfind(prefix, 0) == 0;
}

/// OctoMap's binary (.bt) encoding of a node's subtree (OccupancyOcTreeBase::
/// writeBinaryNode), written here because the library's writer prints "Writing N nodes"
/// to stderr: two bytes of 2-bit child codes (children 0-3, then 4-7; bit 2i set for a
/// free leaf, bit 2i+1 for an occupied one, both for an inner node, none for an unknown
/// child), then the inner children in order. Recursion depth is the tree depth (16).
void writeBinaryNode(std::ostream& out, const octomap::OcTree& tree,
                     const octomap::OcTreeNode* node)
{
  unsigned char codes[2] = {0, 0};
  for (unsigned i = 0; i < 8; ++i) {
    if (!tree.nodeChildExists(node, i))
      continue;
    const octomap::OcTreeNode* child = tree.getNodeChild(node, i);
    const unsigned code = tree.nodeHasChildren(child)  ? 3u
                          : tree.isNodeOccupied(child) ? 2u
                                                       : 1u;
    codes[i / 4] = static_cast<unsigned char>(codes[i / 4] | code << (2 * (i % 4)));
  }
  out.write(reinterpret_cast<const char*>(codes), 2);
  for (unsigned i = 0; i < 8; ++i)
    if (tree.nodeChildExists(node, i) && tree.nodeHasChildren(tree.getNodeChild(node, i)))
      writeBinaryNode(out, tree, tree.getNodeChild(node, i));
}

/// What checkOcTreeNodes found: all nodes, and those with children.
struct NodeCounts {
  std::uint64_t nodes = 0;
  std::uint64_t inner = 0;
};

/// Walks the node data of an OctoMap file without recursion, as OctoMap's readers will
/// (depth first, a node's own bytes before its children's), and refuses what they would
/// recurse into without end or read wrongly: a tree deeper than OctoMap's 16 levels,
/// data that ends inside a node, and a node count other than the header's `size`
/// (when it has one), and in a .ot a log-odds that is not finite. `in` is at the node
/// data and is left after it. .bt: each inner node is 2 bytes, 2 bits per child (01
/// free leaf, 10 occupied leaf, 11 inner node, 00 none). .ot: each node is its float
/// log-odds (OctoMap writes the machine's float: little-endian here) and a byte of
/// child bits.
NodeCounts checkOcTreeNodes(const std::string& path, std::istream& in, bool binary,
                            std::uint64_t header_size, bool have_size)
{
  constexpr int kTreeDepth = 16; // OctoMap's fixed depth: leaves at 16 at the deepest
  std::vector<char> buffer(1 << 16);
  std::size_t pos = 0, end = 0;
  auto readByte = [&](unsigned char& c) {
    if (pos == end) {
      in.read(buffer.data(), static_cast<std::streamsize>(buffer.size()));
      end = static_cast<std::size_t>(in.gcount());
      pos = 0;
      if (end == 0)
        return false;
    }
    c = static_cast<unsigned char>(buffer[pos++]);
    return true;
  };
  auto truncated = [&] {
    return FormatError("'" + path + "' is truncated or not a valid OctoMap " +
                       (binary ? "binary (.bt)" : "(.ot)") +
                       " file: its node data ends inside a node");
  };
  std::uint64_t nodes = 0, inner = 0;
  std::vector<int> pending{0}; // the depths of the nodes still to read, root first
  while (!pending.empty()) {
    const int depth = pending.back();
    pending.pop_back();
    ++nodes;
    unsigned char bytes[5];
    const int n = binary ? 2 : 5;
    for (int i = 0; i < n; ++i)
      if (!readByte(bytes[i]))
        throw truncated();
    int children = 0, leaves = 0;
    if (binary) {
      for (int child = 0; child < 8; ++child) {
        const unsigned bits = (bytes[child / 4] >> (2 * (child % 4))) & 3u;
        children += bits == 3u;
        leaves += bits == 1u || bits == 2u;
      }
    } else {
      for (int child = 0; child < 8; ++child)
        children += (bytes[4] >> child) & 1u;
      float log_odds = 0.0f;
      static_assert(sizeof(float) == 4, "OctoMap's .ot stores 4-byte floats");
      std::memcpy(&log_odds, bytes, 4);
      if (!std::isfinite(log_odds)) {
        std::ostringstream s;
        s << "'" << path << "' holds a node (number " << nodes - 1
          << " from 0) with log-odds " << log_odds << ", expected a finite value";
        throw FormatError(s.str());
      }
    }
    inner += children > 0 || leaves > 0;
    if ((children > 0 || leaves > 0) && depth + 1 > kTreeDepth)
      throw FormatError("'" + path + "' holds a tree deeper than OctoMap's " +
                        std::to_string(kTreeDepth) + " levels");
    nodes += static_cast<std::uint64_t>(leaves);
    // Siblings are alike here (only their depth matters), so a stack reads them in
    // the file's order.
    pending.insert(pending.end(), static_cast<std::size_t>(children), depth + 1);
  }
  if (have_size && nodes != header_size)
    throw FormatError("'" + path + "' holds " + std::to_string(nodes) +
                      " nodes, its header says size " + std::to_string(header_size));
  return {nodes, inner};
}

} // namespace

namespace {

/// The leaves occupiedVoxelCentres expands and the key ranges it expands them to: one
/// rule for occupiedVoxelCount (before anything is allocated) and the expansion.
class OccupiedLeaves {
public:
  OccupiedLeaves(const octomap::OcTree& tree, const OccupiedVoxelOptions& options)
      : tree_(tree), options_(options), depth_(tree.getTreeDepth())
  {
    const double threshold = options.threshold;
    if (std::isnan(threshold) || threshold > 1.0) {
      std::ostringstream s;
      s << "occupiedVoxelCentres: threshold " << threshold
        << " must be an occupancy probability <= 1 (or < 0 for the tree's own)";
      throw InvalidArgumentError(s.str());
    }
    if (options.roi.empty())
      return;
    // Key range (per axis, conservative by one key) that can hold ROI centres: a large
    // pruned node is then expanded only where the ROI is.
    const Box bb = options.roi.boundingBox();
    const double inv = 1.0 / tree.getResolution();
    const std::int64_t max_val = std::int64_t{1} << (depth_ - 1); // key of 0.0
    for (int a = 0; a < 3; ++a) {
      roi_lo_[a] =
          static_cast<std::int64_t>(std::max(std::floor(bb.min()[a] * inv), -1e9)) +
          max_val - 1;
      roi_hi_[a] =
          static_cast<std::int64_t>(std::min(std::floor(bb.max()[a] * inv), 1e9)) +
          max_val + 1;
    }
  }

  /// Calls f(lo, hi) for every occupied leaf with the keys [lo, hi] per axis that it
  /// expands to (empty when lo > hi on an axis), in OctoMap's leaf iteration order
  /// (depth first, children 0 to 7).
  template <typename F>
  void forEach(F&& f) const
  {
    if (const octomap::OcTreeNode* root = tree_.getRoot()) {
      const std::int64_t lo[3] = {0, 0, 0};
      walk(*root, 0, lo, f);
    }
  }

  /// A subtree that forEach walks whole: its node, depth and first key per axis.
  struct Subtree {
    const octomap::OcTreeNode* node;
    unsigned depth;
    std::int64_t lo[3];
  };

  /// The subtrees at `depth` (and the leaves above it) that forEach walks, in its order:
  /// forEach is forEachIn of each in turn.
  std::vector<Subtree> subtrees(unsigned depth) const
  {
    std::vector<Subtree> out;
    if (const octomap::OcTreeNode* root = tree_.getRoot()) {
      const std::int64_t lo[3] = {0, 0, 0};
      split(*root, 0, lo, depth, out);
    }
    return out;
  }

  /// forEach's calls for the leaves of one subtree.
  template <typename F>
  void forEachIn(const Subtree& subtree, F&& f) const
  {
    walk(*subtree.node, subtree.depth, subtree.lo, f);
  }

  /// The voxels forEach visits, without allocating.
  double count() const
  {
    double count = 0.0;
    forEach(
        [&](const std::int64_t* lo, const std::int64_t* hi) { count += voxels(lo, hi); });
    return count;
  }

  /// The voxels of the key ranges [lo, hi] (0 when empty on an axis).
  static double voxels(const std::int64_t* lo, const std::int64_t* hi)
  {
    double voxels = 1.0;
    for (int a = 0; a < 3; ++a)
      voxels *= static_cast<double>(std::max<std::int64_t>(hi[a] - lo[a] + 1, 0));
    return voxels;
  }

private:
  bool occupied(const octomap::OcTreeNode& node) const
  {
    const double threshold = options_.threshold;
    return threshold < 0.0 ? tree_.isNodeOccupied(node) : node.getOccupancy() > threshold;
  }

  /// The first keys of child i of a node of n keys a side starting at `lo`: the upper
  /// half of axis a where bit a of i is set (OctoMap's child index).
  static void childKeys(const std::int64_t lo[3], std::int64_t n, unsigned i,
                        std::int64_t child_lo[3])
  {
    for (unsigned a = 0; a < 3; ++a)
      child_lo[a] = lo[a] + (((i >> a) & 1u) ? n / 2 : 0);
  }

  /// The node at `depth` whose keys start at `lo` per axis.
  template <typename F>
  void walk(const octomap::OcTreeNode& node, unsigned depth, const std::int64_t lo[3],
            F& f) const
  {
    const std::int64_t n = std::int64_t{1} << (depth_ - depth); // keys per axis
    if (tree_.nodeHasChildren(&node)) {
      // An inner node holding its children's maximum is occupied when any is.
      if (options_.inner_nodes_hold_max && !occupied(node))
        return;
      for (unsigned i = 0; i < 8; ++i) {
        if (!tree_.nodeChildExists(&node, i))
          continue;
        std::int64_t child_lo[3];
        childKeys(lo, n, i, child_lo);
        walk(*tree_.getNodeChild(&node, i), depth + 1, child_lo, f);
      }
      return;
    }
    if (!occupied(node))
      return;
    std::int64_t leaf_lo[3], leaf_hi[3];
    for (int a = 0; a < 3; ++a) {
      leaf_lo[a] = lo[a];
      leaf_hi[a] = lo[a] + n - 1;
      if (!options_.roi.empty()) {
        leaf_lo[a] = std::max(leaf_lo[a], roi_lo_[a]);
        leaf_hi[a] = std::min(leaf_hi[a], roi_hi_[a]);
      }
    }
    f(static_cast<const std::int64_t*>(leaf_lo),
      static_cast<const std::int64_t*>(leaf_hi));
  }

  /// walk's descent down to `split_depth`, keeping the subtrees there instead of
  /// walking them.
  void split(const octomap::OcTreeNode& node, unsigned depth, const std::int64_t lo[3],
             unsigned split_depth, std::vector<Subtree>& out) const
  {
    if (depth == split_depth || !tree_.nodeHasChildren(&node)) {
      out.push_back({&node, depth, {lo[0], lo[1], lo[2]}});
      return;
    }
    if (options_.inner_nodes_hold_max && !occupied(node))
      return;
    const std::int64_t n = std::int64_t{1} << (depth_ - depth);
    for (unsigned i = 0; i < 8; ++i) {
      if (!tree_.nodeChildExists(&node, i))
        continue;
      std::int64_t child_lo[3];
      childKeys(lo, n, i, child_lo);
      split(*tree_.getNodeChild(&node, i), depth + 1, child_lo, split_depth, out);
    }
  }

  const octomap::OcTree& tree_;
  const OccupiedVoxelOptions& options_;
  const unsigned depth_;
  std::int64_t roi_lo_[3] = {0, 0, 0}, roi_hi_[3] = {0, 0, 0};
};

} // namespace

double occupiedVoxelCount(const octomap::OcTree& tree,
                          const OccupiedVoxelOptions& options)
{
  return OccupiedLeaves(tree, options).count();
}

namespace {

/// Each key of the ranges [lo, hi] per axis, z fastest.
template <typename Emit>
void forEachKey(const std::int64_t* lo, const std::int64_t* hi, Emit&& emit)
{
  octomap::OcTreeKey key;
  for (std::int64_t kx = lo[0]; kx <= hi[0]; ++kx)
    for (std::int64_t ky = lo[1]; ky <= hi[1]; ++ky)
      for (std::int64_t kz = lo[2]; kz <= hi[2]; ++kz) {
        key[0] = static_cast<octomap::key_type>(kx);
        key[1] = static_cast<octomap::key_type>(ky);
        key[2] = static_cast<octomap::key_type>(kz);
        emit(key);
      }
}

/// An occupied leaf's keys [lo, hi] per axis (OccupiedLeaves::forEach, not empty: keys
/// of a tree of depth 16).
struct KeyRange {
  std::uint16_t lo[3];
  std::uint16_t hi[3];
};

/// forEachKey over a KeyRange.
template <typename Emit>
void forEachKey(const KeyRange& r, Emit&& emit)
{
  const std::int64_t lo[3] = {r.lo[0], r.lo[1], r.lo[2]};
  const std::int64_t hi[3] = {r.hi[0], r.hi[1], r.hi[2]};
  forEachKey(lo, hi, emit);
}

/// The depth of the subtrees that threads walk: nodes of 32 voxels a side, hundreds of
/// them on a plant's map.
constexpr unsigned kSubtreeDepth = 11;

} // namespace

void occupiedVoxelCentres(const octomap::OcTree& tree, CloudXYZ& cloud,
                          const OccupiedVoxelOptions& options)
{
  if (options.threads < 0)
    throw InvalidArgumentError(
        "occupiedVoxelCentres: " + std::to_string(options.threads) +
        " threads, expected >= 0 (0 = OpenMP's default)");
  const OccupiedLeaves leaves(tree, options);
  const int threads = options.threads > 0 ? options.threads : omp_get_max_threads();
  // Subtrees on several threads, each writing from its first point on: their points
  // are known ahead only without a ROI (its exact test keeps some of them).
  const bool parallel = threads > 1 && options.roi.empty();
  std::vector<OccupiedLeaves::Subtree> subtrees;
  std::vector<double> subtree_points;
  // On one thread the walk keeps the occupied leaves' key ranges (12 bytes a leaf, fewer
  // than the points, kept only while those are within the cap) and the points are made
  // from them: one walk of the tree instead of two.
  std::vector<KeyRange> ranges;
  const auto pointBytes = [](double points) {
    return points * static_cast<double>(sizeof(pcl::PointXYZ));
  };
  double points = 0.0;
  if (parallel) {
    subtrees = leaves.subtrees(kSubtreeDepth);
    subtree_points.assign(subtrees.size(), 0.0);
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(subtrees.size()); ++i) {
      double count = 0.0;
      leaves.forEachIn(subtrees[static_cast<std::size_t>(i)],
                       [&](const std::int64_t* lo, const std::int64_t* hi) {
                         count += OccupiedLeaves::voxels(lo, hi);
                       });
      subtree_points[static_cast<std::size_t>(i)] = count;
    }
    for (double count : subtree_points)
      points += count; // whole numbers: the same sum as count()'s
  } else {
    leaves.forEach([&](const std::int64_t* lo, const std::int64_t* hi) {
      const double voxels = OccupiedLeaves::voxels(lo, hi);
      points += voxels; // the same sum as count()'s
      if (voxels > 0.0 && pointBytes(points) <= options.memory_cap_bytes)
        ranges.push_back(
            {{static_cast<std::uint16_t>(lo[0]), static_cast<std::uint16_t>(lo[1]),
              static_cast<std::uint16_t>(lo[2])},
             {static_cast<std::uint16_t>(hi[0]), static_cast<std::uint16_t>(hi[1]),
              static_cast<std::uint16_t>(hi[2])}});
    });
  }
  std::ostringstream what;
  what << std::setprecision(3) << "the octree's occupied voxels of "
       << tree.getResolution() << " m (" << points << " points)";
  requireWithinMemoryCap(pointBytes(points), options.memory_cap_bytes, what.str());
  cloud.clear();
  const auto centre = [&tree](const octomap::OcTreeKey& key) {
    return Eigen::Vector3d(tree.keyToCoord(key[0]), tree.keyToCoord(key[1]),
                           tree.keyToCoord(key[2]));
  };
  const auto point = [](const Eigen::Vector3d& c) {
    return pcl::PointXYZ(static_cast<float>(c.x()), static_cast<float>(c.y()),
                         static_cast<float>(c.z()));
  };
  if (parallel) {
    cloud.resize(static_cast<std::size_t>(points));
    std::vector<std::size_t> first(subtrees.size());
    std::size_t next = 0;
    for (std::size_t i = 0; i < subtrees.size(); ++i) {
      first[i] = next;
      next += static_cast<std::size_t>(subtree_points[i]);
    }
#pragma omp parallel for num_threads(threads) schedule(dynamic, 1)
    for (std::ptrdiff_t i = 0; i < static_cast<std::ptrdiff_t>(subtrees.size()); ++i) {
      std::size_t k = first[static_cast<std::size_t>(i)];
      leaves.forEachIn(subtrees[static_cast<std::size_t>(i)],
                       [&](const std::int64_t* lo, const std::int64_t* hi) {
                         forEachKey(lo, hi, [&](const octomap::OcTreeKey& key) {
                           cloud[k++] = point(centre(key));
                         });
                       });
    }
  } else if (options.roi.empty()) {
    cloud.resize(static_cast<std::size_t>(points));
    std::size_t k = 0;
    for (const KeyRange& r : ranges)
      forEachKey(r,
                 [&](const octomap::OcTreeKey& key) { cloud[k++] = point(centre(key)); });
  } else {
    for (const KeyRange& r : ranges)
      forEachKey(r, [&](const octomap::OcTreeKey& key) {
        const Eigen::Vector3d c = centre(key);
        if (options.roi.contains(c))
          cloud.push_back(point(c));
      });
  }
  cloud.width = static_cast<std::uint32_t>(cloud.size());
  cloud.height = 1;
  cloud.is_dense = true;
}

std::unique_ptr<octomap::OcTree> cloudToOcTree(const CloudXYZ& cloud, double resolution)
{
  if (!(std::isfinite(resolution) && resolution > 0.0)) {
    std::ostringstream s;
    s << "cloudToOcTree: resolution " << resolution << " must be finite and > 0 (metres)";
    throw InvalidArgumentError(s.str());
  }
  auto tree = std::make_unique<octomap::OcTree>(resolution);
  const VoxelLattice lattice(resolution);

  // Distinct voxels first: a voxel hit by several points gets one hit, so the result
  // depends on the set of voxels only, not on point density or order.
  octomap::KeySet keys;
  for (const pcl::PointXYZ& p : cloud) {
    if (!pcl::isXYZFinite(p)) // NaNs crash OctoMap's key arithmetic
      continue;
    // OctoMap's coordToKey casts floor(coord / res) to int unchecked: range-checked here.
    const float xyz[3] = {p.x, p.y, p.z};
    int k[3];
    if (!lattice.coordToKey(xyz, k)) {
      std::ostringstream s;
      s << "cloudToOcTree: point (" << p.x << ", " << p.y << ", " << p.z
        << ") lies outside the octree's range of +-"
        << VoxelLattice::kKeyOffset * resolution << " m at resolution " << resolution;
      throw InvalidArgumentError(s.str());
    }
    keys.insert(octomap::OcTreeKey(static_cast<octomap::key_type>(k[0]),
                                   static_cast<octomap::key_type>(k[1]),
                                   static_cast<octomap::key_type>(k[2])));
  }
  for (const octomap::OcTreeKey& key : keys)
    tree->updateNode(key, true, /*lazy_eval=*/true);
  // Lazy updates leave inner nodes stale and the tree unpruned.
  tree->updateInnerOccupancy();
  tree->prune();
  return tree;
}

std::unique_ptr<octomap::OcTree> readOcTree(const std::string& path,
                                            bool* maximum_likelihood)
{
  // Checked here so that a missing file is an IoError before OctoMap prints anything.
  std::error_code ec;
  if (!std::filesystem::exists(path, ec))
    throw FileNotFoundError("octree file '" + path + "' does not exist");
  if (std::filesystem::is_directory(path, ec))
    throw IoError("octree file '" + path + "' is a directory");
  // Opening a FIFO blocks until something writes to it; a device can be endless.
  if (!std::filesystem::is_regular_file(path, ec))
    throw IoError("octree file '" + path +
                  "' is not a regular file (a FIFO, socket or device)");
  std::ifstream in(path, std::ios::binary);
  if (!in)
    throw IoError("cannot open octree file '" + path + "' for reading");

  // The content decides, not the extension: .bt and .ot start with their own header.
  std::string first_line;
  std::getline(in, first_line);
  const bool binary = startsWith(first_line, kBinaryHeader);
  if (binary || startsWith(first_line, kFullHeader)) {
    if (maximum_likelihood)
      *maximum_likelihood = binary;
    // The rest of OctoMap's header (AbstractOcTree::readHeader), read here because the
    // library's readers print to stdout and stderr: "id", "size", "res", comments,
    // "data"; then the nodes, in OctoMap's binary or full layout.
    const char* kind = binary ? "binary (.bt)" : "(.ot)";
    std::string id, token;
    double res = 0.0;
    std::uint64_t size = 0;
    bool have_size = false;
    while (in >> token) {
      if (token == "data") {
        in.ignore(std::numeric_limits<std::streamsize>::max(), '\n'); // rest of the line
        break;
      }
      if (token == "id")
        in >> id;
      else if (token == "res") {
        // Read as text, so that "nan" or "1e-300x" is named rather than failing the
        // stream; every value is then checked against the range.
        std::string text;
        in >> text;
        char* end = nullptr;
        res = std::strtod(text.c_str(), &end);
        if (text.empty() || *end != '\0')
          throw FormatError("'" + path + "' has resolution '" + text +
                            "', expected a number of metres");
      } else if (token == "size")
        have_size = static_cast<bool>(in >> size);
      else {
        std::string rest;
        std::getline(in, rest); // "size", comments and unknown lines
      }
    }
    if (!in || token != "data")
      throw FormatError("'" + path + "' is not a valid OctoMap " + kind +
                        " file: its header has no 'data' line");
    if (id != "OcTree")
      throw FormatError("'" + path + "' holds an OctoMap " + (id.empty() ? "?" : id) +
                        ", expected an OcTree");
    if (!(res >= kMinMapResolutionM && res <= kMaxMapResolutionM)) {
      std::ostringstream s;
      s << "'" << path << "' has resolution " << res << " m, expected "
        << kMinMapResolutionM << " to " << kMaxMapResolutionM << " m";
      throw FormatError(s.str());
    }
    // OctoMap's readers recurse as deep as the data says: checked first, then re-read.
    const std::streampos body = in.tellg();
    const NodeCounts counts = checkOcTreeNodes(path, in, binary, size, have_size);
    // An OcTreeNode is 16 bytes, and a node with children has an array of 8 pointers.
    const double need = 16.0 * static_cast<double>(counts.nodes) +
                        64.0 * static_cast<double>(counts.inner);
    try {
      requireWithinMemoryCap(need, kDefaultMemoryCapBytes,
                             "'" + path + "': its " + std::to_string(counts.nodes) +
                                 " nodes");
    } catch (const InvalidArgumentError& e) {
      throw FormatError(e.what());
    }
    in.clear();
    in.seekg(body);
    auto tree = std::make_unique<octomap::OcTree>(res);
    if (binary)
      tree->readBinaryData(in);
    else
      tree->readData(in);
    if (in.bad())
      throw IoError("error while reading octree file '" + path + "'");
    if (in.fail())
      throw FormatError("'" + path + "' is truncated or not a valid OctoMap " +
                        std::string(kind) + " file");
    return tree;
  }
  throw FormatError("'" + path + "' is not an OctoMap file (expected the header '" +
                    kBinaryHeader + "' or '" + kFullHeader + "')");
}

void writeOcTree(const std::string& path, const octomap::OcTree& tree)
{
  const std::string ext = lowerExtension(path);
  if (ext != ".bt" && ext != ".ot")
    throw FormatError("cannot write octree file '" + path + "': extension '" + ext +
                      "' is neither .bt nor .ot");
  // An existing map is replaced whole or not at all, never left half-written.
  AtomicFile file(path);
  std::ostream& out = file.stream();
  // OctoMap's file layout (AbstractOcTree::write, AbstractOccupancyOcTree::writeBinary),
  // written here because the library's writers print to stderr, and writeBinary would
  // turn the caller's tree into maximum likelihood. `res` with the stream's default
  // formatting, as OctoMap writes it.
  const bool binary = ext == ".bt";
  out << (binary ? kBinaryHeader : kFullHeader)
      << "\n# (feel free to add / change comments, but leave the first line as it "
         "is!)\n#\n"
      << "id " << tree.getTreeType() << "\nsize " << tree.size() << "\nres "
      << tree.getResolution() << "\ndata\n";
  if (binary) {
    if (tree.getRoot())
      writeBinaryNode(out, tree, tree.getRoot());
  } else
    tree.writeData(out);
  file.commit();
}

} // namespace plantnbv
