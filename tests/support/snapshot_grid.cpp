// Renders the ten default plants (seeds 0-9, base at the origin, yaw 0) with their
// whole-plant, main-stem and leaf-node ROIs, 400 x 500 px each, into one 2 x 5 grid:
//   snapshot_grid docs/images/default-plants.png
// Re-executes itself under xvfb-run when there is no X display.

#include <chrono>
#include <cstdio>
#include <exception>
#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/plant/plant_rois.h>
#include <plantnbv/plant/tomato_plant_generator.h>
#include <plantnbv/viz/display.h>
#include <plantnbv/viz/snapshot.h>

namespace viz = plantnbv::viz;

int main(int argc, char** argv)
{
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s OUTPUT.png\n", argv[0]);
    return 1;
  }
  if (!viz::reexecUnderXvfbIfNeeded(argc, argv)) {
    try {
      viz::requireDisplay();
    } catch (const plantnbv::Error& e) {
      std::fprintf(stderr, "error: %s\n", e.what());
    }
    return 1;
  }
  try {
    constexpr int kColumns = 5, kRows = 2, kTileWidth = 400, kTileHeight = 500;
    viz::RgbImage grid;
    grid.width = kColumns * kTileWidth;
    grid.height = kRows * kTileHeight;
    grid.rgb.assign(std::size_t(3) * grid.width * grid.height, 255);
    for (int i = 0; i < plantnbv::kDefaultPlantCount; ++i) {
      plantnbv::Plant plant =
          plantnbv::TomatoPlantGenerator(plantnbv::defaultPlantConfig(i)).generate();
      plantnbv::posePlant(plant, Eigen::Vector3d::Zero(), 0.0);
      viz::SceneSnapshot::Config config;
      config.width = kTileWidth;
      config.height = kTileHeight;
      config.title = "seed " + std::to_string(i);
      config.title_size_px = 26;
      viz::SceneSnapshot snapshot(config);
      snapshot.addMesh(plant.mesh);
      snapshot.addRoi(plantnbv::wholePlantRoi(plant), viz::distinctColor(0));
      snapshot.addRoi(plantnbv::mainStemRoi(plant), viz::distinctColor(1));
      snapshot.addRoi(plantnbv::leafNodeRoi(plant), viz::distinctColor(2));
      const auto start = std::chrono::steady_clock::now();
      const viz::RgbImage tile = snapshot.renderImage();
      const double ms = std::chrono::duration<double, std::milli>(
                            std::chrono::steady_clock::now() - start)
                            .count();
      std::printf("seed %d: %zu triangles, rendered in %.0f ms\n", i, plant.mesh.size(),
                  ms);
      const int x0 = (i % kColumns) * kTileWidth, y0 = (i / kColumns) * kTileHeight;
      for (int y = 0; y < kTileHeight; ++y)
        for (int x = 0; x < kTileWidth; ++x) {
          std::uint8_t* out = grid.at(x0 + x, y0 + y);
          // A light grey frame around each tile separates the plants.
          const bool frame =
              x == 0 || y == 0 || x == kTileWidth - 1 || y == kTileHeight - 1;
          for (int c = 0; c < 3; ++c)
            out[c] = frame ? 210 : tile.at(x, y)[c];
        }
    }
    viz::writePng(grid, argv[1]);
    std::printf("wrote %s (%d x %d)\n", argv[1], grid.width, grid.height);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
