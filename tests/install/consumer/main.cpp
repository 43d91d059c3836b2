// Two 1 mm-spaced rows of points, the second 1 mm above the first: every point's nearest
// neighbour in the other cloud is 1 mm away, so Chamfer = 2 mm and, at rho = 3 mm, F1
// = 1.
#include <iostream>

#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include <plantnbv/metrics/reconstruction_metrics.h>

int main()
{
  auto a = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  auto b = std::make_shared<pcl::PointCloud<pcl::PointXYZ>>();
  for (int i = 0; i < 100; ++i) {
    a->push_back(pcl::PointXYZ(0.001f * i, 0.0f, 0.0f));
    b->push_back(pcl::PointXYZ(0.001f * i, 0.0f, 0.001f));
  }
  plantnbv::ReconstructionMetrics metrics;
  metrics.setReference(a);
  metrics.setReconstruction(b);
  metrics.setThreshold(0.003);
  const plantnbv::MetricsResult m = metrics.compute();
  std::cout << "f1=" << m.f1 << " chamfer=" << static_cast<float>(m.chamfer) << "\n";
  return m.valid ? 0 : 1;
}
