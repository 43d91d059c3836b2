// Writes the synthetic test plant as a binary PLY with face labels; made
// data/fixtures/plant_like.ply (detail 16). Usage: write_synthetic_plant OUT.ply [DETAIL]
#include <iostream>
#include <string>

#include <plantnbv/common/error.h>
#include <plantnbv/io/mesh_io.h>

#include "synthetic_plant.h"

int main(int argc, char** argv)
{
  if (argc < 2 || argc > 3) {
    std::cerr << "usage: write_synthetic_plant OUT.ply [DETAIL]\n";
    return 2;
  }
  try {
    plantnbv::test::SyntheticPlantConfig config;
    if (argc == 3)
      config.detail = std::stoi(argv[2]);
    const plantnbv::TriangleMesh mesh = plantnbv::test::makeSyntheticPlant(config);
    plantnbv::io::saveMeshPly(argv[1], mesh);
    std::cout << "wrote " << argv[1] << ": " << mesh.vertices.size() << " vertices, "
              << mesh.size() << " triangles\n";
  } catch (const std::exception& e) {
    std::cerr << "write_synthetic_plant: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
