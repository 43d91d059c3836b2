#pragma once
/// \file octree_conversion.h
/// \brief Conversions between OctoMap octrees and point clouds, and .bt/.ot files.

#include <memory>
#include <string>

#include <plantnbv/common/box.h>
#include <plantnbv/common/memory_cap.h>
#include <plantnbv/common/pcl_fwd.h>

namespace octomap {
class OcTree;
}

namespace plantnbv {

/// \brief The voxel sizes a map may have, in metres: 0.1 mm (the tree then spans
/// +-3.3 m around the origin) to 10 m. OccupancyMap::Config and the .bt / .ot reader
/// refuse anything else (0, negative, NaN, 1e-300, 1e300).
constexpr double kMinMapResolutionM = 1e-4;
/// \brief The largest voxel size a map may have: 10 m (see kMinMapResolutionM).
constexpr double kMaxMapResolutionM = 10.0;

/// \brief Options for `occupiedVoxelCentres`.
struct OccupiedVoxelOptions {
  /// Occupancy probability above which a voxel counts (strict >); a value < 0 uses the
  /// tree's own occupancy threshold (OctoMap's isNodeOccupied, default 0.5).
  double threshold = -1.0;
  /// When non-empty, only voxels whose centre lies in the ROI are kept.
  Roi roi;
  /// The most bytes the cloud may take (16 per point): a pruned node of a tiny file can
  /// stand for 2^48 voxels. Over it, nothing is allocated.
  double memory_cap_bytes = kDefaultMemoryCapBytes;
  /// The tree's inner nodes hold the maximum of their children's log-odds (OctoMap's
  /// non-lazy updates and updateInnerOccupancy() leave them so; OccupancyMap's always
  /// are): a subtree whose node is not occupied holds no occupied voxel and is not
  /// walked. The same points either way on such a tree, far faster on a map of mostly
  /// free space; on another tree, occupied voxels would be missed.
  bool inner_nodes_hold_max = false;
  /// Threads of the walk (default 1; 0: OpenMP's default). The same points in the same
  /// order for any count; with a ROI the walk takes one thread.
  int threads = 1;
};

/// \brief The number of points `occupiedVoxelCentres` gives with `options` before the
/// ROI's exact test: every occupied leaf's voxels (a pruned leaf at depth d has
/// 8^(16 - d)), clipped to the ROI's key range. O(leaves), allocates nothing.
/// \throws InvalidArgumentError if options.threshold is NaN or > 1.
double occupiedVoxelCount(const octomap::OcTree& tree,
                          const OccupiedVoxelOptions& options = {});

/// \brief The centres of the occupied voxels at the tree's finest resolution: a pruned
/// inner node stands for all its voxels and is expanded into them (keys computed, not
/// searched). Centre of key k: (k - 32768 + 0.5) * resolution in double (OctoMap's
/// keyToCoord), stored as float; the same points as VoxelGridFilter's centre mode.
/// Order: OctoMap's leaf iteration order, each expanded node in increasing (x, y, z) key
/// order (z fastest).
/// \param[in] tree the map; not modified. \param[out] cloud cleared, then filled
/// (unorganized, dense). \throws InvalidArgumentError if options.threshold is NaN or > 1,
/// options.threads < 0, or if occupiedVoxelCount(tree, options) points exceed
/// options.memory_cap_bytes (the message gives both; checked before anything is
/// allocated).
void occupiedVoxelCentres(const octomap::OcTree& tree, CloudXYZ& cloud,
                          const OccupiedVoxelOptions& options = {});

/// \brief A new octree at `resolution` in which the voxel of every finite point is
/// occupied (one hit each, however many points share the voxel: OctoMap's default hit
/// probability 0.7) and nothing else is known. Non-finite points are skipped. The tree is
/// pruned (a full block of equal voxels becomes one node).
/// \throws InvalidArgumentError unless the resolution is finite and > 0, or if a point
/// lies outside the octree's range (+-32768 voxels around the origin).
std::unique_ptr<octomap::OcTree> cloudToOcTree(const CloudXYZ& cloud, double resolution);

/// \brief Reads a .bt (binary, maximum-likelihood) or .ot (full) octree file; the file's
/// header line decides which, not its extension.
/// The header is parsed here (OctoMap's header reader prints to stderr) and the node
/// data is walked and checked before OctoMap's node reader (silent on checked data;
/// it recurses as deep as the data says) builds the tree: depth 16, the header's node
/// count, a resolution in [kMinMapResolutionM, kMaxMapResolutionM], finite log-odds in
/// a .ot, and the tree's memory (about 16 bytes a node and 64 an inner node) within
/// kDefaultMemoryCapBytes. Nothing is printed; thread-safe (no global state).
/// \throws IoError if missing or unreadable; FormatError if it is not an OctoMap file,
/// holds another tree type (e.g. a ColorOcTree) or fails a check, naming the file and
/// the value.
/// \param[out] maximum_likelihood if not null, whether the file was a .bt.
std::unique_ptr<octomap::OcTree> readOcTree(const std::string& path,
                                            bool* maximum_likelihood = nullptr);

/// \brief Writes .bt (writeBinaryConst) or .ot (write), by extension, as OctoMap's
/// own tools (octovis, binvox2bt) read them; .bt stores occupied / free only (the tree
/// itself is not changed). The extension is matched case-insensitively. The file is
/// written as `path`.partial and renamed: an existing file is replaced whole or kept.
/// \throws IoError if the file cannot be written; FormatError for another extension
/// (checked before the file is created).
void writeOcTree(const std::string& path, const octomap::OcTree& tree);

} // namespace plantnbv
