#pragma once
// The parts of the module, one per area of the library (module.cpp calls them in order:
// a part may use the types of the parts before it).

#include <pybind11/pybind11.h>

namespace plantnbv {
namespace python {

void bindErrors(pybind11::module_& m);
/// Box, Roi, poses and frames, camera intrinsics, part labels, Mesh.
void bindGeometry(pybind11::module_& m);
/// Metrics, filters, mesh sampling, cloud / mesh / ROI / depth files.
void bindClouds(pybind11::module_& m);
/// Plants (generated, models, scans), their ROIs, the simulated depth camera.
void bindPlants(pybind11::module_& m);
/// OccupancyMap, candidate samplers, planners, the active-vision session.
void bindPlanning(pybind11::module_& m);
/// Trials and campaigns.
void bindExperiment(pybind11::module_& m);

} // namespace python
} // namespace plantnbv
