#pragma once
/// \file trial_config_file.h
/// \brief A trial's configuration from YAML (data/paper.yaml is the paper's Table 1).

#include <string>

#include <plantnbv/experiment/trial.h>

namespace YAML {
class Node;
}

namespace plantnbv {
namespace io {
class YamlReader;
}
namespace scenario {

/// \brief Overwrites the fields of `config` that the YAML file at `path` sets, then
/// validates it. Keys (all optional; metres, degrees where the key says _deg):
/// \code{.yaml}
/// camera: l515 | l515-640 | l515-320 | WxH:fx,fy,cx,cy
/// noise: bool
/// views: int
/// depth_scale: number (depth units per metre; 0: the sensor's float depth)
/// planner: nbv | predefined | random        pattern: 1-4
/// stop_gain_bits: number                    seed: int
/// explore_share: number in [0, 1]          view_spacing: number (metres)
/// time_limit_s: number (0: none)            memory_cap_gib: number (default 8)
/// initial_view: {position: [x, y, z], orientation: [qx, qy, qz, qw]}
/// sector: {radius, height, bottom, angle_deg, rows, cols, samples_per_cell}
/// map: {resolution, prob_hit, prob_miss, clamp_min, clamp_max, occupancy_threshold,
///       max_range}
/// gain: {rays_x, rays_y, raycast_range, visibility_weighted, unknown_only,
///        unknown_depth}
/// scene: {floor: bool, support: bool}
/// \endcode
/// An empty file changes nothing.
/// \throws IoError if the file cannot be read; FormatError naming the key path for an
/// unknown key or a value of the wrong type; InvalidArgumentError for an out-of-range
/// value.
void loadTrialConfig(const std::string& path, TrialConfig& config);

/// \brief The keys of loadTrialConfig from a map already parsed (e.g. the `trial:`
/// section of a campaign file) at key path `path` ("trial"). Does not validate (the
/// caller does, after its own overrides). \throws FormatError as loadTrialConfig.
void readTrialConfig(const io::YamlReader& reader, const YAML::Node& node,
                     const std::string& path, TrialConfig& config);

/// \brief `config` as a trial config file: every key loadTrialConfig reads, numbers in
/// their shortest form that reads back exactly, so that loading the text gives the same
/// values (v0's orientation to rounding: it is normalized again when read). The rest of
/// TrialConfig (the noise model's constants, the threads) is not written. The camera is
/// named by its preset (l515, l515-640, l515-320) when it is one, else written as
/// WxH:fx,fy,cx,cy, whose range limits are the presets'. A campaign's fingerprint
/// includes it, so that results made under other built-in defaults are another
/// campaign's.
std::string trialConfigText(const TrialConfig& config);

} // namespace scenario
} // namespace plantnbv
