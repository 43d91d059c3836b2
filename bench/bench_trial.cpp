/// \file bench_trial.cpp
/// \brief The whole time of one 10-view trial (plantnbv::Trial): setup (sensor scene,
/// ground truth), then per view plan + capture + insert + evaluate, at 1 and 2 threads.
///
/// Data: default tomato plants 3 and 9 (defaultPlantConfig) posed at the paper's
/// (1.0, 0, 0.8), yaw 0, in the default scene (floor and support); the paper's Table 1
/// (TrialConfig defaults: L515 at 640 x 480, 3 mm map, 27 candidates, 10 views from v0);
/// evaluation at whole plant, main stem, leaf nodes and fruits. Planners: NBV with
/// attention on the whole plant and on the leaf nodes, and random. One iteration = one
/// Trial::run (plant generation not included); counters give the sums over the 10 views
/// of each phase (plan_ms, capture_ms, insert_ms, eval_ms), setup_ms, and the final
/// leaf-node F1. `full_map` 0: Trial::setKeepFullMap(false), as a campaign runs its
/// trials (the same steps and scores, the free space that nothing reads left out).
/// BM_Evaluation times a trial's evaluation alone, without the noise of the rest of
/// the trial: `views:0` is the evaluator's setup in a trial (setGroundTruth, setLevels,
/// setBackground), `views:10` the scores and organ recall of the ten reconstructions a
/// whole-plant NBV trial of the plant has after each of its views, in order.
/// BM_OccupiedVoxelCentres times the occupied voxels' centres of such a trial's last map.
/// Run (machine quiet):
///   bench_trial --benchmark_repetitions=3 --benchmark_report_aggregates_only=true

#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/experiment/plant_scene.h>
#include <plantnbv/experiment/reconstruction_evaluator.h>
#include <plantnbv/experiment/trial.h>
#include <plantnbv/octree/occupancy_map.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>

namespace {

using namespace plantnbv;

std::shared_ptr<const Plant> defaultPlant(int seed)
{
  auto plant =
      std::make_shared<Plant>(TomatoPlantGenerator(defaultPlantConfig(seed)).generate());
  posePlant(*plant, paperPlantBase(), 0.0);
  return plant;
}

const std::shared_ptr<const Plant>& cachedPlant(int seed)
{
  static std::shared_ptr<const Plant> plants[10];
  if (!plants[seed])
    plants[seed] = defaultPlant(seed);
  return plants[seed];
}

std::vector<EvaluationLevel> evaluationLevels(const Plant& plant)
{
  return {{"whole_plant", wholePlantRoi(plant)},
          {"main_stem", mainStemRoi(plant)},
          {"leaf_nodes", leafNodeRoi(plant), true},
          {"fruit", fruitRoi(plant), true}};
}

/// planner: 0 = NBV whole plant, 1 = NBV leaf nodes, 2 = random.
void BM_Trial(benchmark::State& state)
{
  const int seed = int(state.range(0));
  const int planner = int(state.range(1));
  const int threads = int(state.range(2));
  const bool full_map = state.range(3) != 0;
  const Plant& plant = *cachedPlant(seed);

  TrialConfig config;
  config.planner = planner == 2 ? PlannerKind::random : PlannerKind::nbv;
  config.threads = threads;
  config.seed = 1;
  Trial trial(config);
  trial.setKeepFullMap(full_map);
  trial.setPlant(cachedPlant(seed));
  trial.setAttentionRoi(planner == 1 ? leafNodeRoi(plant) : wholePlantRoi(plant));
  trial.setEvaluationLevels(evaluationLevels(plant));
  TrialResult result;
  for (auto _ : state) {
    trial.run(result);
    state.SetIterationTime(result.total_ms / 1000.0);
  }
  double plan = 0, capture = 0, insert = 0, eval = 0;
  for (const TrialStep& s : result.steps) {
    plan += s.plan_ms;
    capture += s.capture_ms;
    insert += s.insert_ms;
    eval += s.eval_ms;
  }
  state.counters["setup_ms"] = result.setup_ms;
  state.counters["plan_ms"] = plan;
  state.counters["capture_ms"] = capture;
  state.counters["insert_ms"] = insert;
  state.counters["eval_ms"] = eval;
  state.counters["views"] = double(result.steps.size());
  state.counters["leaf_nodes_f1"] = result.steps.back().scores[2].f1;
}

BENCHMARK(BM_Trial)
    ->ArgsProduct({{3, 9}, {0, 1, 2}, {1, 2}, {1, 0}})
    ->ArgNames({"plant", "planner", "threads", "full_map"})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1);

/// views: 0 = the evaluator's setup (ground truth), 10 = the ten views' evaluations in
/// order, each of the reconstruction the trial's map had after that view (a new
/// evaluator each iteration, set up outside the timing).
void BM_Evaluation(benchmark::State& state)
{
  const int seed = int(state.range(0));
  const bool views = state.range(1) != 0;
  const int threads = int(state.range(2));
  const Plant& plant = *cachedPlant(seed);
  TrialConfig config;
  config.seed = 1;
  static std::vector<CloudXYZ> reconstructions[10]; // per plant, one per view
  std::vector<CloudXYZ>& reconstruction = reconstructions[seed];
  if (views && reconstruction.empty()) {
    Trial trial(config);
    trial.setPlant(cachedPlant(seed));
    trial.setAttentionRoi(wholePlantRoi(plant));
    trial.setEvaluationLevels(evaluationLevels(plant));
    trial.setStepCallback([&](const TrialStep&) {
      reconstruction.emplace_back();
      trial.getMap().getOccupiedVoxelCentres(reconstruction.back());
    });
    TrialResult result;
    trial.run(result);
  }
  TriangleMesh background;
  for (const TriangleMesh& part : plantSceneBackground(plant, config.scene))
    background.append(part);
  const auto setUp = [&](ReconstructionEvaluator& evaluator) {
    evaluator.setResolution(config.map.resolution_m);
    evaluator.setSeed(groundTruthSeed(config.seed));
    evaluator.setNumberOfThreads(threads);
    evaluator.setGroundTruth(plant);
    evaluator.setLevels(evaluationLevels(plant));
    evaluator.setBackground(background);
  };
  std::vector<LevelScore> scores;
  std::vector<OrganRecall> organs;
  for (auto _ : state) {
    ReconstructionEvaluator evaluator;
    if (views) {
      state.PauseTiming();
      setUp(evaluator);
      state.ResumeTiming();
      for (const CloudXYZ& view : reconstruction)
        evaluator.compute(view, scores, organs);
    } else {
      setUp(evaluator);
    }
  }
  if (views) {
    state.counters["views"] = double(reconstruction.size());
    state.counters["occupied_voxels"] = double(reconstruction.back().size());
  }
}

BENCHMARK(BM_Evaluation)
    ->ArgsProduct({{3, 9}, {0, 10}, {1, 2}})
    ->ArgNames({"plant", "views", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

/// The occupied voxels' centres (OccupancyMap::getOccupiedVoxelCentres, what each view's
/// evaluation starts with) of the map a whole-plant NBV trial of the plant has after its
/// 10 views, as a campaign runs it (the update region), on the trial's threads.
void BM_OccupiedVoxelCentres(benchmark::State& state)
{
  const int seed = int(state.range(0));
  TrialConfig config;
  config.threads = int(state.range(1));
  config.seed = 1;
  Trial trial(config);
  trial.setPlant(cachedPlant(seed));
  trial.setAttentionRoi(wholePlantRoi(*cachedPlant(seed)));
  trial.setEvaluationLevels(evaluationLevels(*cachedPlant(seed)));
  TrialResult result;
  trial.run(result);
  CloudXYZ occupied;
  for (auto _ : state)
    trial.getMap().getOccupiedVoxelCentres(occupied);
  state.counters["occupied_voxels"] = double(occupied.size());
}

BENCHMARK(BM_OccupiedVoxelCentres)
    ->ArgsProduct({{3, 9}, {1, 2}})
    ->ArgNames({"plant", "threads"})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

} // namespace

BENCHMARK_MAIN();
