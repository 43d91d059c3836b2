#include <algorithm>

#include <plantnbv/common/roi_kind.h>

namespace plantnbv {

namespace {

struct RoiKindInfo {
  const char* name;
  const char* title;
  bool boxes_apart;
};

// Indexed by RoiKind.
constexpr RoiKindInfo kInfo[] = {
    {"whole_plant", "Whole plant", false},
    {"main_stem", "Main stem", false},
    {"leaf_nodes", "Leaf nodes", true},
    {"fruit", "Fruit", true},
};

const RoiKindInfo& info(RoiKind kind)
{
  return kInfo[static_cast<int>(kind)];
}

} // namespace

const char* roiKindName(RoiKind kind)
{
  return info(kind).name;
}

std::optional<RoiKind> roiKindFromName(const std::string& name)
{
  std::string canonical = name;
  std::replace(canonical.begin(), canonical.end(), '-', '_');
  if (canonical == "fruits")
    canonical = "fruit";
  for (RoiKind kind : kRoiKinds)
    if (canonical == info(kind).name)
      return kind;
  return std::nullopt;
}

const char* roiKindTitle(RoiKind kind)
{
  return info(kind).title;
}

std::string roiTitle(const std::string& name)
{
  const std::optional<RoiKind> kind = roiKindFromName(name);
  return kind ? roiKindTitle(*kind) : name;
}

bool roiKindScoresBoxesApart(RoiKind kind)
{
  return info(kind).boxes_apart;
}

std::string roiKindNames()
{
  std::string names;
  for (RoiKind kind : kRoiKinds)
    names += (names.empty() ? "" : ", ") + std::string(info(kind).name);
  return names;
}

} // namespace plantnbv
