#pragma once
/// \file tomato_plant_generator.h
/// \brief Procedural greenhouse tomato plants (young, indeterminate) with part labels and
/// anatomy, reproducible from a seed. The botany and the source of every range are in
/// docs/plants.md.

#include <cstdint>
#include <string>
#include <vector>

#include <plantnbv/plant/plant.h>

namespace plantnbv {

/// \brief Generates a tomato plant from a growth stage and a seed.
///
/// One main stem (radius 2.5-4.5 mm, height 0.45-0.70 m to the apex, slightly curved,
/// base at the origin, z up); compound leaves in a spiral phyllotaxis (divergence near
/// 137.5 deg) at internodes that lengthen with the growth stage and shorten towards the
/// apex; each leaf a petiole and rachis of 0.15-0.40 m drooping along its length, with
/// 2-4 pairs of leaflets and a terminal one (leaflets 3-9 cm long, 2-4 cm wide, curved
/// and serrate); trusses on the internode above every third leaf from the 4th-7th leaf
/// on, each with 2-6 fruits of radius 1.2-3 cm. `growth_stage` moves all of these
/// together; the seed adds per-plant variation within the ranges, which are hard limits.
/// Nothing reaches below the base; the highest leaf tip stays under 0.70 m (at most 0.686
/// m over 1500 seeds tried), so the paper's 0.7 m tall ROIs hold the plant's height.
///
/// Determinism: the mesh depends only on the Config. Draws come from `Rng` (one stream
/// per plant, leaf and truss, so removing leaflets or trusses shifts no other draw) and
/// trigonometry from portable_math.h, so the mesh is bit-identical across machines,
/// compilers, optimisation levels and thread counts. Generation is single-threaded.
///
/// Mesh: about 160k (youngest default plant) to 245k (oldest) triangles at mesh_detail 1;
/// one named part per organ ("stem", "leaf_03_petiole", "leaf_03_leaflet_2",
/// "truss_0_peduncle", "truss_0_pedicel_1", "truss_0_fruit_1") with its PartLabel (the
/// rachis counts as petiole, pedicels as peduncle). Leaflets are single surfaces facing
/// up (docs/plants.md says why): ray casters and renderers must not cull back faces.
/// \code
/// TomatoPlantGenerator generator(defaultPlantConfig(3));
/// Plant plant = generator.generate();
/// posePlant(plant, Eigen::Vector3d(1.0, 0.0, 0.8), 0.0);
/// \endcode
/// generate() is const and may be called from several threads at once.
class TomatoPlantGenerator {
public:
  /// \brief Everything that defines a plant. Defaults give a mid-stage plant.
  struct Config {
    /// Per-plant variation: the same seed and Config give the same plant (default 0).
    std::uint64_t seed = 0;
    /// Development, from a young plant (0: stem about 0.47 m, 10-13 leaves, one or two
    /// trusses of fruit up to 2 cm radius) to an older one (1: about 0.64 m, 11-14
    /// leaves, two or three trusses of fruit up to 3 cm). In [0, 1]; default 0.5.
    double growth_stage = 0.5;
    /// Scale of the seed's random variation around the stage's typical plant: 0 gives
    /// the typical plant (the seed then does not matter), 1 the documented ranges. In
    /// [0, 1]; default 1.
    double variation = 1.0;
    /// Mean angle between successive leaves around the stem (rad); each plant deviates
    /// by up to 2.5 deg and each leaf by up to 4 deg more. In (0, pi]; default 137.5 deg,
    /// the golden angle of spiral phyllotaxis.
    double divergence_angle_rad = 2.399827721492203;
    /// Remove half of the leaflets of every leaf (one of each pair, alternating sides;
    /// the terminal leaflet stays), as the paper's reduced-occlusion experiment did.
    /// Everything else is unchanged. Default false.
    bool simplified = false;
    /// Scales the mesh resolution (segments around tubes, rows along leaflets): about
    /// quadratic in triangle count. In [0.25, 4]; default 1 (edges of about 2 mm).
    double mesh_detail = 1.0;

    /// \brief One line per field, for logs.
    std::string toString() const;
  };

  /// \brief A generator with the default Config.
  TomatoPlantGenerator() = default;
  /// \throws InvalidArgumentError if a field of `config` is out of its range.
  explicit TomatoPlantGenerator(const Config& config);

  /// \brief Replaces the whole configuration. \throws InvalidArgumentError naming the
  /// first field out of range.
  void setConfig(const Config& config);
  /// \brief The configuration the next generate() uses.
  const Config& getConfig() const { return config_; }

  /// \brief Config::seed: the per-plant variation.
  void setSeed(std::uint64_t seed) { config_.seed = seed; }
  /// \param[in] stage in [0, 1]; \throws InvalidArgumentError otherwise.
  void setGrowthStage(double stage);
  /// \param[in] variation in [0, 1]; \throws InvalidArgumentError otherwise.
  void setVariation(double variation);
  /// \param[in] angle_rad in (0, pi]; \throws InvalidArgumentError otherwise.
  void setDivergenceAngle(double angle_rad);
  /// \brief Config::simplified: half of the leaflets removed.
  void setSimplified(bool simplified) { config_.simplified = simplified; }
  /// \param[in] detail in [0.25, 4]; \throws InvalidArgumentError otherwise.
  void setMeshDetail(double detail);

  /// \brief Builds the plant in the plant frame (base at the origin, yaw 0).
  Plant generate() const;

private:
  Config config_;
};

/// \brief Number of plants in the default set (the paper used ten).
constexpr int kDefaultPlantCount = 10;

/// \brief Config of plant `index` (0-9) of the default set: seed = index and growth
/// stage = index / 9, so the set spans the growth stages evenly from the youngest
/// (index 0) to the oldest plant (index 9), like the paper's ten models of different
/// growth stages. \throws InvalidArgumentError unless 0 <= index < kDefaultPlantCount.
TomatoPlantGenerator::Config defaultPlantConfig(int index, bool simplified = false);

/// \brief The ten configs of the default set, in index order.
std::vector<TomatoPlantGenerator::Config> defaultPlantSet(bool simplified = false);

} // namespace plantnbv
