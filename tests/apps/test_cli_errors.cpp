// Every subcommand's bad arguments and files, as a table: each gives exit code 1 (bad
// input) or 2 (usage error) and one line on stderr that names what was wrong.

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <string>
#include <sys/stat.h>
#include <vector>

#include <gtest/gtest.h>

#include "cli_fixture.h"

namespace fs = std::filesystem;

using plantnbv::test::CliTest;
using plantnbv::test::expectOneLineError;
using plantnbv::test::kFixtures;
using plantnbv::test::slurp;
using plantnbv::test::ToolRun;

namespace {

struct BadCall {
  std::string args;   ///< "{d}" stands for the test's directory, "{f}" for the fixtures
  int code;           ///< 1 bad input, 2 usage error
  std::string needle; ///< what the message must name ("{d}" as in args)
};

const std::vector<BadCall> kBadCalls = {
    // usage errors: CLI11's parse errors, mapped to 2
    {"", 2, "subcommand"},
    {"frobnicate", 2, "frobnicate"},
    {"eval --reference a.pcd", 2, "--reconstruction"},
    {"eval --reference a.pcd --reconstruction b.pcd --bogus", 2, "--bogus"},
    {"eval --reference a.pcd --reconstruction b.pcd --rho", 2, "--rho"},
    {"sample --mesh m.ply --points many -o x.pcd", 2, "--points"},
    {"plant --seed 1 --model m.dae -o {d}/x", 2, "excludes"},
    {"plant --seed 1 --labels stem=.* -o {d}/x", 2, "--model"},
    {"capture --plant 1 --pose 1,2,3 -o {d}/v.pcd", 2, "--pose"},
    {"capture --plant 1 --noise-seed 3 -o {d}/v.pcd", 2, "--noise"},
    {"reconstruct --plant 1", 2, "--output"},
    {"campaign run {d}/tiny.yaml", 2, "--output"},
    {"campaign run {d}/tiny.yaml -o {d}/c -j -1", 2,
     "--jobs: expected 0 (all cores) or a number of trials at a time, got '-1'"},
    {"campaign run-chunk {d}/tiny.yaml -o {d}/c --chunk 0 --chunks 1 -j 2.5", 2,
     "--jobs: expected 0 (all cores)"},
    {"campaign report", 2, "dir"},
    // eval
    {"eval --reference {d}/missing.pcd --reconstruction {d}/a.pcd", 1, "missing.pcd"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/empty.obj", 1, "empty.obj"},
    {"eval --reference {d}/garbage.ply --reconstruction {d}/a.pcd", 1, "garbage.ply"},
    {"eval --reference {d}/nan.pcd --reconstruction {d}/a.pcd", 1, "no finite point"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --rho 0", 1, "--rho"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --rho -1", 1, "--rho"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --resolution 0", 1,
     "--resolution"},
    {"eval --reference {d}/cloud.xyz --reconstruction {d}/a.pcd", 1, ".xyz"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --roi {d}/negative.yaml", 1,
     "negative.yaml"},
    // sample
    {"sample --mesh {d}/missing.obj -o {d}/o.pcd", 1, "missing.obj"},
    {"sample --mesh {f}/plant_like.ply --points 0 -o {d}/o.pcd", 1, "--points"},
    {"sample --mesh {f}/plant_like.ply -o {d}/o.txt", 1, "o.txt"},
    {"sample --mesh {f}/plant_like.ply --voxel -0.1 -o {d}/o.pcd", 1, "--voxel"},
    // plant
    {"plant --seed 1 --stage -1 -o {d}/x", 1, "growth_stage"},
    {"plant --model {f}/plant_cm_zup.dae --labels trunk=.* -o {d}/x", 1, "trunk"},
    {"plant --model {d}/nothing.dae -o {d}/x", 1, "nothing.dae"},
    {"plant -o {d}/x", 1, "--seed"},
    {"plant --seed 1 --base 1,2 -o {d}/x", 1, "--base"},
    // unsigned options: no wrapping of negatives, no saturation past 2^64 - 1
    {"plant --seed -5 -o {d}/x", 2, "--seed: expected a whole number from 0 to"},
    {"plant --seed 18446744073709551616 -o {d}/x", 2, "got '18446744073709551616'"},
    {"plant --seed 0x10 -o {d}/x", 2, "--seed"},
    {"capture --plant 1 --noise-seed -1 -o {d}/v.pcd", 2, "--noise-seed"},
    {"reconstruct --plant 1 --seed -3 -o {d}/x", 2, "--seed"},
    {"sample --mesh {f}/plant_like.ply --points -100 -o {d}/o.pcd", 2, "--points"},
    {"eval --reference {f}/plant_like.ply --reconstruction {f}/plant_like.ply "
     "--mesh-points -1",
     2, "--mesh-points"},
    {"plan --map {d}/m.ot --seed 99999999999999999999", 2, "--seed"},
    // capture
    {"capture -o {d}/v.pcd", 1, "--plant"},
    {"capture --plant 1 --pose 1,2,3,0,0,0,0 -o {d}/v.pcd", 1, "quaternion"},
    {"capture --plant 1 --pose nan,2,3,0,0,0,1 -o {d}/v.pcd", 1, "--pose"},
    {"capture --plant 1 --intrinsics l516 -o {d}/v.pcd", 1, "l516"},
    {"capture --plant 1 --resolution -1 --map {d}/m.bt -o {d}/v.pcd", 1, "resolution"},
    {"capture --plant 1 -o {d}/v.xyz", 1, "v.xyz"},
    {"capture --plant 1", 1,
     "nothing to write: give -o CLOUD, --frames-out FRAMES, --depth PNG, --map MAP or "
     "--snapshot PNG"},
    {"capture --plant 1 --map {d}/m.vdb -o {d}/v.pcd", 1, "m.vdb"},
    // reconstruct
    {"reconstruct --plant 1 --planner greedy -o {d}/x", 1, "greedy"},
    {"reconstruct --plant 1 --candidates 10 -o {d}/x", 1, "--candidates"},
    {"reconstruct --plant 1 --pattern 5 --planner predefined -o {d}/x", 1, "pattern"},
    {"reconstruct --plant 1 --views 0 -o {d}/x", 1, "views"},
    {"reconstruct --plant 1 --attention stems -o {d}/x", 1, "stems"},
    {"reconstruct --model {f}/plant_cm_zup.dae --attention leaf-nodes -o {d}/x", 1,
     "leaf_nodes"},
    {"reconstruct --plant 1 --config {d}/misspelt.yaml -o {d}/x", 1, "hieght"},
    {"reconstruct --plant 1 --config {d}/words.yaml -o {d}/x", 1, "views"},
    {"reconstruct --plant 1 --config {d}/none.yaml -o {d}/x", 1, "none.yaml"},
    {"reconstruct --plant 1 --config {d}/nan_view.yaml -o {d}/x", 1, "initial_view"},
    {"reconstruct --plant 1 --resolution 0.0004 -o {d}/x", 1, "over the memory cap"},
    {"reconstruct --plant 1 --config {d}/time_limit.yaml -o {d}/x", 1, "time_limit_s"},
    // campaign
    {"campaign run {d}/missing.yaml -o {d}/c", 1, "missing.yaml"},
    {"campaign run {d}/unknown_key.yaml -o {d}/c", 1, "studies[0].planners[0].atention"},
    {"campaign run {d}/garbage.yaml -o {d}/c", 1, "garbage.yaml"},
    {"campaign status {d}/nowhere", 1, "nowhere"},
    {"campaign report {d}/nowhere", 1, "nowhere"},
    {"campaign run-chunk {d}/tiny.yaml -o {d}/c --chunk 3 --chunks 2", 1, "chunk"},
    {"campaign run-chunk {d}/tiny.yaml -o {d}/c --chunk 0 --chunks 0", 1,
     "chunk 0 of 0: expected 0 <= chunk < chunks"},
    {"campaign run-chunk {d}/tiny.yaml -o {d}/c --chunk -1 --chunks 3", 1,
     "chunk -1 of 3: expected 0 <= chunk < chunks"},
    // YAML that would make a reader recurse, or that says a key twice; what is not a file
    {"reconstruct --plant 1 --config {d}/self_alias.yaml -o {d}/x", 1,
     "self_alias.yaml' (line 1): a value holds an alias of itself"},
    {"reconstruct --plant 1 --config {d}/deep.yaml -o {d}/x", 1, "nested deeper than 32"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --roi {d}/twice.yaml", 1,
     "(line 4): key 'size' appears twice (first on line 3)"},
    {"campaign run {d}/laughs.yaml -o {d}/c", 1, "aliases expand the document"},
    {"reconstruct --plant 1 --config {d}/dir.yaml -o {d}/x", 1,
     "dir.yaml: is a directory, expected a file"},
    {"campaign run {d}/fifo.yaml -o {d}/c", 1, "fifo.yaml: is not a regular file"},
    // integrate: frames folders with one defect each (copies of {d}/good, see the test)
    {"integrate {d}/nocamera -o {d}/m.ot", 1, "nocamera/camera.yaml': no such file"},
    {"integrate {d}/nomatrix -o {d}/m.ot", 1,
     "nomatrix/camera.yaml' camera_matrix: missing"},
    {"integrate {d}/wordwidth -o {d}/m.ot", 1,
     "wordwidth/camera.yaml' image_width: 'wide' is not an integer"},
    {"integrate {d}/wordmatrix -o {d}/m.ot", 1,
     "wordmatrix/camera.yaml' camera_matrix.data: expected 9 numbers, got [fx, 0, 159.5"},
    {"integrate {d}/wrongsize -o {d}/m.ot", 1,
     "wrongsize/depth/000000.png' is 320x240, camera.yaml says 640x240"},
    {"integrate {d}/grey8 -o {d}/m.ot", 1,
     "grey8/depth/000000.png' is not a 16-bit grey PNG"},
    {"integrate {d}/colour -o {d}/m.ot", 1,
     "colour/depth/000000.png' is not a 16-bit grey PNG"},
    {"integrate {d}/colour16 -o {d}/m.ot", 1,
     "colour16/depth/000000.png' is not a 16-bit grey PNG"},
    {"integrate {d}/truncated -o {d}/m.ot", 1,
     "cannot decode depth image '{d}/truncated/depth/000000.png'"},
    {"integrate {d}/cutheader -o {d}/m.ot", 1,
     "cutheader/depth/000000.png' is not a PNG file"},
    {"integrate {d}/nopng -o {d}/m.ot", 1, "{d}/nopng/depth/000009.png: no such file"},
    {"integrate {d}/pose6 -o {d}/m.ot", 1,
     "pose6/groundtruth.txt' line 3: expected 8 numbers "
     "'timestamp tx ty tz qx qy qz qw', got 6"},
    {"integrate {d}/pose9 -o {d}/m.ot", 1,
     "pose9/groundtruth.txt' line 3: expected 8 numbers "
     "'timestamp tx ty tz qx qy qz qw', got 9"},
    {"integrate {d}/posenan -o {d}/m.ot", 1,
     "posenan/groundtruth.txt' line 3: tz 'nan' is not a finite number"},
    {"integrate {d}/poseinf -o {d}/m.ot", 1,
     "poseinf/groundtruth.txt' line 3: qw '-inf' is not a finite number"},
    {"integrate {d}/zeroquat -o {d}/m.ot", 1,
     "zeroquat/groundtruth.txt' line 3: quaternion (0, 0, 0, 0) has norm 0"},
    {"integrate {d}/nopose -o {d}/m.ot", 1,
     "nopose/depth.txt' line 3: frame 'depth/000000.png' (0.000000 s) has no pose in "
     "'{d}/nopose/groundtruth.txt' within 0.02 s (nearest 0.021000 s)"},
    {"integrate {d}/scale0 -o {d}/m.ot", 1,
     "scale0/camera.yaml' depth_scale: expected units per metre > 0 (1000: millimetres), "
     "got 0"},
    {"integrate {d}/scaleneg -o {d}/m.ot", 1, "scaleneg/camera.yaml' depth_scale"},
    {"integrate {d}/good -o {d}/m.ot --depth-scale 0", 1, "--depth-scale 0"},
    {"integrate {d}/good -o {d}/m.ot --depth-scale -1000", 1, "--depth-scale -1000"},
    {"integrate {d}/distorted -o {d}/m.ot", 1,
     "distorted/camera.yaml' distortion_coefficients.data: non-zero distortion "
     "[0.1, 0, 0, 0, 0]"},
    {"integrate {d}/empty -o {d}/m.ot", 1, "empty/camera.yaml': no such file"},
    {"integrate {d}/nowhere -o {d}/m.ot", 1, "nowhere': no such folder"},
    {"integrate {d}/good -o {d}/m.txt", 1, "m.txt': expected a .ot (log-odds) or .bt"},
    {"integrate {d}/good -o {d}/m.ot --frames 9", 1, "--frames '9': '9' is out of range"},
    {"integrate {d}/good -o {d}/m.ot --frames abc", 1,
     "--frames 'abc': 'abc' is not an index or a range"},
    {"integrate {d}/good --map-in {d}/notamap.ot -o {d}/m.ot", 1,
     "notamap.ot' is not an OctoMap file"},
    {"integrate {d}/good --map-in {d}/cut.ot -o {d}/m.ot", 1,
     "cut.ot' is truncated or not a valid OctoMap (.ot) file"},
    // plan (on {d}/good.ot, the map of {d}/good, unless the map is what is wrong)
    {"plan --map {d}/notamap.ot", 1, "notamap.ot' is not an OctoMap file"},
    {"plan --map {d}/good.ot --visited {d}/nope.txt", 1, "nope.txt: no such file"},
    {"plan --map {d}/notamap.bt", 1, "notamap.bt' is not an OctoMap file"},
    {"plan --map {d}/cut.ot", 1,
     "cut.ot' is truncated or not a valid OctoMap (.ot) file"},
    {"plan --map {d}/none.ot", 1, "none.ot' does not exist"},
    {"plan --map {d}/good.txt", 1, "good.txt': expected a .ot (log-odds) or .bt"},
    {"plan --map {d}/good.ot --top -1", 1, "--top -1: expected K >= 0"},
    {"plan --map {d}/good.ot --top two", 2, "--top"},
    {"plan --map {d}/good.ot --roi leaf_nodes", 1,
     "--roi leaf_nodes: leaf nodes and fruit are where a plant's anatomy puts them"},
    {"plan --map {d}/good.ot --roi stems", 1, "--roi: unknown ROI 'stems'"},
    {"plan --map {d}/good.ot --roi {d}/noroi.yaml", 1, "noroi.yaml"},
    {"plan --map {d}/good.ot --sector-base 1,0", 2, "--sector-base"},
    {"plan --map {d}/good.ot --current-pose 1,0,1,0,0,0,0", 1,
     "--current-pose: pose quaternion must not be zero"},
    {"plan --map {d}/good.ot --travel-cost 5", 1, "--travel-cost needs --current-pose"},
    {"plan --map {d}/good.ot --candidates 10", 1,
     "--candidates 10: expected a multiple of the 9 grid cells"},
    {"plan --map {d}/good.ot --json --pose-only", 2, "excludes"},
    // Tiny inputs that expand to gigabytes: refused up front with the estimate; maps
    // with a resolution out of range or a NaN node; ROI boxes without volume (the
    // hand-made files are written below, next to notamap.ot)
    {"eval --reference {d}/root_leaves.bt --reconstruction {d}/a.pcd", 1,
     "root_leaves.bt': the octree's occupied voxels of 0.003 m (2.81e+14 points) need "
     "about 4.19e+06 GiB, over the memory cap of 8 GiB"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/root.ot", 1,
     "root.ot': the octree's occupied voxels of 0.005 m (2.81e+14 points) need about"},
    {"plan --map {d}/root.ot", 1, "--map '{d}/root.ot': InformationGain::update"},
    {"plan --map {d}/tiny_res.bt", 1,
     "tiny_res.bt' has resolution 1e-300 m, expected 0.0001 to 10 m"},
    {"eval --reference {d}/huge_res.bt --reconstruction {d}/a.pcd", 1,
     "huge_res.bt' has resolution 1e+300 m, expected 0.0001 to 10 m"},
    {"integrate {d}/good --map-in {d}/nan_res.ot -o {d}/m.ot", 1,
     "nan_res.ot' has resolution nan m, expected 0.0001 to 10 m"},
    {"integrate {d}/good --map-in {d}/word_res.ot -o {d}/m.ot", 1,
     "word_res.ot' has resolution 'fine', expected a number of metres"},
    {"plan --map {d}/nan_node.ot", 1,
     "nan_node.ot' holds a node (number 1 from 0) with log-odds nan, expected a finite "
     "value"},
    {"capture --plant 1 --resolution 0.0001 --map {d}/m.ot", 1,
     "--intrinsics 640x480 and --resolution 0.0001 m (map range 0.75 m) need about "
     "6.16e+03 GiB, over the memory cap of 8 GiB"},
    {"capture --plant 1 --intrinsics 16384x16384:9000,9000,8191.5,8191.5 --map {d}/m.bt",
     1,
     "--intrinsics 16384x16384 and --resolution 0.003 m (map range 0.75 m) need about"},
    {"capture --plant 1 --resolution 0.00005 --map {d}/m.ot", 1,
     "resolution_m = 5e-05 must be in [0.0001, 10] (metres)"},
    {"integrate {d}/good -o {d}/m.ot --resolution 0.0001", 1,
     "the map at 0.0001 m (range 0.75 m) of the 320x240 camera of '{d}/good' need about"},
    {"sample --mesh {f}/plant_like.ply --points 1000000000 -o {d}/o.pcd", 1,
     "--points 1000000000 need about 44.7 GiB, over the memory cap of 8 GiB"},
    {"sample --mesh {f}/plant_like.ply --labels --points 300000000 -o {d}/o.pcd", 1,
     "--points 300000000 need about 22.4 GiB"},
    {"eval --reference {f}/plant_like.ply --reconstruction {d}/a.pcd --mesh-points "
     "2000000000",
     1, "the 2000000000 surface samples of '{f}/plant_like.ply' need about"},
    {"eval --reference {d}/a.pcd --reconstruction {d}/a.pcd --roi {d}/flat.yaml", 1,
     "flat.yaml' boxes[0].size: expected 3 sizes > 0 (metres), got [0.1, 0, 0.1]"},
    {"plan --map {d}/good.ot --roi {d}/point.yaml", 1,
     "point.yaml' boxes[1].size: expected 3 sizes > 0 (metres), got [0, 0, 0]"},
    // Values that were taken silently: a yaw beyond a turn, a pattern the planner
    // ignores, images named .jpg that would hold PNG bytes, the grid's own multiples
    {"reconstruct --plant 1 --yaw-deg 1e19 -o {d}/x", 2,
     "--yaw-deg: expected a number from -360 to 360 (degrees), got '1e19'"},
    {"plant --seed 1 --yaw-deg -360.5 -o {d}/x", 2, "--yaw-deg"},
    {"capture --plant 1 --yaw-deg nan -o {d}/v.pcd", 2, "--yaw-deg"},
    {"campaign run {d}/yaw.yaml -o {d}/c", 1,
     "yaw.yaml' yaws_deg[1]: expected an angle in [-360, 360] degrees, got 1e19"},
    {"reconstruct --plant 1 --planner nbv --pattern 2 -o {d}/x", 1,
     "--pattern 2: only the predefined planner has patterns (the planner is nbv)"},
    {"reconstruct --plant 1 --planner random --pattern 1 -o {d}/x", 1,
     "(the planner is random)"},
    {"plant --seed 1 --snapshot {d}/x.jpg -o {d}/x", 2,
     "--snapshot: expected a file name ending in .png (the image is written as PNG), "
     "got"},
    {"capture --plant 1 --depth {d}/c.jpeg -o {d}/c.pcd", 2,
     "--depth: expected a file name ending in .png"},
    {"plant --model {f}/plant_like.ply --model {d}/scan.pcd -o {d}/x", 1,
     "scan.pcd': a plant split into several files takes mesh files"},
    {"capture --plant 1 --snapshot {d}/c.jpg", 2,
     "--snapshot: expected a file name ending in .png"},
    {"reconstruct --plant 1 --snapshot {d}/x.jpg -o {d}/x", 2,
     "--snapshot: expected a file name ending in .png"},
    {"reconstruct --plant 1 -o {d}/x --snapshot", 2, "--snapshot"},
    {"reconstruct --plant 1 --intrinsics l516 -o {d}/x", 1, "--intrinsics: "},
    {"reconstruct --plant 1 --intrinsics 640x480:0,500,320,240 -o {d}/x", 1,
     "--intrinsics: "},
    {"reconstruct --plant 1 --config {d}/grid8.yaml --candidates 27 -o {d}/x", 1,
     "--candidates 27: expected a multiple of the 8 grid cells (8, 24, 40, ...)"},
    {"reconstruct --plant 1 --roi-source detector -o {d}/x", 1,
     "--roi-source: unknown ROI source 'detector' (expected oracle, noisy, "
     "detections, prior or detections+prior)"},
    {"reconstruct --plant 1 --roi-sigma 0.01 -o {d}/x", 1,
     "--roi-sigma 0.01: only the noisy ROI source uses it (--roi-source is oracle)"},
    {"reconstruct --plant 1 --roi-source noisy --roi-sigma -0.01 -o {d}/x", 1,
     "--roi-sigma -0.01: expected a finite value >= 0 (metres)"},
    {"reconstruct --plant 1 --roi-source noisy --roi-scale 0 -o {d}/x", 1,
     "--roi-scale 0: expected a finite value > 0"},
    {"reconstruct --plant 1 --roi-source noisy --roi-sigma nan -o {d}/x", 1,
     "--roi-sigma nan: expected a finite value >= 0 (metres)"},
    {"reconstruct --plant 1 --detector-recall 0.5 -o {d}/x", 1,
     "--detector-recall 0.5: only the detections and detections+prior ROI sources use "
     "it (--roi-source is oracle)"},
    {"reconstruct --plant 1 --roi-source detections --detector-recall 1.5 -o {d}/x", 1,
     "--detector-recall 1.5: expected a value in [0, 1]"},
    {"reconstruct --plant 1 --roi-source detections --detector-false-positives -2 -o "
     "{d}/x",
     1, "--detector-false-positives -2: expected a value in [0, 1000] per frame"},
    {"reconstruct --plant 1 --detector-mask-dilation 2 -o {d}/x", 1,
     "--detector-mask-dilation 2: only the detections and detections+prior ROI sources "
     "use it (--roi-source is oracle)"},
    {"reconstruct --plant 1 --roi-source detections --detector-mask-dilation 65 -o {d}/x",
     1, "--detector-mask-dilation 65: expected pixels in [-64, 64]"},
    {"reconstruct --plant 1 --roi-source detections --detector-box-jitter -1 -o {d}/x", 1,
     "--detector-box-jitter -1: expected a value in [0, 1000] (pixels)"},
    {"reconstruct --plant 1 --roi-source detections --detector-box-jitter 2 -o {d}/x", 1,
     "--detector-box-jitter 2: the fusion back-projects the detector's masks, not its "
     "boxes; set --detector-masks false for a boxes-only detector"},
    {"reconstruct --plant 1 --detector-masks false -o {d}/x", 1,
     "--detector-masks false: only the detections and detections+prior ROI sources use "
     "it (--roi-source is oracle)"},
    {"plan --map {d}/m.ot --roi-source detections", 1,
     "--roi-source detections: give the detections' 3D boxes as --roi FILE"},
    {"plan --map {d}/m.ot --roi-source detections+prior --roi main_stem", 1,
     "--roi-source detections+prior: give the detections' 3D boxes as --roi FILE"},
    {"plan --map {d}/m.ot --roi-source prior --roi main_stem", 1,
     "--roi-source prior: the prior predicts the ROI from the map, --roi main_stem is "
     "not used"},
    {"plan --map {d}/m.ot --roi-source detections --detector-recall 0.5", 2,
     "--detector-recall"},
    {"reconstruct --plant 1 --roi-source noisy --prior-internode 0.05 -o {d}/x", 1,
     "--prior-internode 0.05: only the prior and detections+prior ROI sources use it "
     "(--roi-source is noisy)"},
    {"reconstruct --plant 1 --roi-source prior --prior-internode 0 -o {d}/x", 1,
     "--prior-internode 0: expected a finite value > 0 (metres)"},
    {"plan --map {d}/m.ot --detector-recall 0.5", 2, "--detector-recall"},
    {"plan --map {d}/m.ot --stem-roi {d}/s.yaml", 1,
     "--stem-roi: only the prior and detections+prior ROI sources use it (--roi-source "
     "is oracle)"},
    {"reconstruct --plant 1 --roi-source prior --detections-explore-views 0 -o {d}/x", 1,
     "--detections-explore-views 0: only the detections ROI source uses it "
     "(--roi-source is prior)"},
    {"reconstruct --plant 1 --roi-source detections --detections-explore-views -1 -o "
     "{d}/x",
     1,
     "--detections-explore-views -1: expected views in [0, 1000] (0: attend from the "
     "first plan)"},
    {"integrate {d}/good -o {d}/m.ot --roi-out {d}/r.txt", 1,
     "--roi-out '{d}/r.txt': expected a file name ending in .yaml"},
    {"integrate {d}/good -o {d}/m.ot --roi-out {d}/r.yaml --roi-class ''", 1,
     "--roi-class '': DetectionFusion: class_name: empty"},
    {"plan --map {d}/m.ot --roi-scale 2", 1,
     "--roi-scale 2: only the noisy ROI source uses it (--roi-source is oracle)"},
};

/// The bytes of a PNG (no filter, deflate's stored blocks): `depth` bits per sample,
/// `colour_type` as in its IHDR (0 grey, 2 RGB), every sample 1.
std::string pngBytes(std::uint32_t width, std::uint32_t height, int depth,
                     int colour_type)
{
  const auto be32 = [](std::uint32_t v) {
    return std::string{char(v >> 24), char(v >> 16), char(v >> 8), char(v)};
  };
  const auto crc32 = [](const std::string& bytes) {
    std::uint32_t c = 0xffffffffu;
    for (unsigned char b : bytes) {
      c ^= b;
      for (int k = 0; k < 8; ++k)
        c = (c >> 1) ^ (0xedb88320u & (0u - (c & 1u)));
    }
    return c ^ 0xffffffffu;
  };
  const std::size_t row = std::size_t(width) * (colour_type == 2 ? 3 : 1) * depth / 8;
  std::string raw;
  for (std::uint32_t y = 0; y < height; ++y)
    raw += '\0' + std::string(row, '\1'); // filter 0, then the samples
  std::string z = "\x78\x01";             // zlib, no compression
  for (std::size_t at = 0; at < raw.size(); at += 65535) {
    const std::size_t n = std::min<std::size_t>(65535, raw.size() - at);
    z += char(at + n == raw.size() ? 1 : 0);
    z += std::string{char(n), char(n >> 8), char(~n), char(~n >> 8)};
    z += raw.substr(at, n);
  }
  std::uint32_t a = 1, b = 0; // Adler-32
  for (unsigned char c : raw) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  z += be32((b << 16) | a);
  const auto chunk = [&](const std::string& type, const std::string& data) {
    return be32(std::uint32_t(data.size())) + type + data + be32(crc32(type + data));
  };
  const std::string ihdr =
      be32(width) + be32(height) + char(depth) + char(colour_type) + std::string(3, '\0');
  return "\x89PNG\r\n\x1a\n" + chunk("IHDR", ihdr) + chunk("IDAT", z) + chunk("IEND", "");
}

/// Rewrites a file with `edit` applied to its text.
void editFile(const fs::path& file, const std::function<void(std::string&)>& edit)
{
  std::string text = slurp(file);
  edit(text);
  std::ofstream(file, std::ios::binary) << text;
}

/// `edit` of the fields of the last line (groundtruth.txt's pose line).
void editLastLine(const fs::path& file,
                  const std::function<void(std::vector<std::string>&)>& edit)
{
  editFile(file, [&](std::string& text) {
    const std::size_t at = text.rfind('\n', text.size() - 2) + 1;
    std::istringstream line(text.substr(at));
    std::vector<std::string> fields;
    for (std::string f; line >> f;)
      fields.push_back(f);
    edit(fields);
    std::string joined;
    for (const std::string& f : fields)
      joined += (joined.empty() ? "" : " ") + f;
    text = text.substr(0, at) + joined + "\n";
  });
}

/// Replaces the first `from` by `to`; fails the test if `from` is not there.
std::function<void(std::string&)> replacing(const std::string& from,
                                            const std::string& to)
{
  return [=](std::string& text) {
    const auto at = text.find(from);
    ASSERT_NE(at, std::string::npos) << "no '" << from << "' in: " << text;
    text.replace(at, from.size(), to);
  };
}

} // namespace

TEST_F(CliTest, EveryBadArgumentOrFileIsOneLineNamingIt)
{
  writeLattice("a.pcd", 0.0f);
  write("empty.obj", "# no faces\nv 0 0 0\n");
  write("garbage.ply", "this is not a ply file\n");
  write("nan.pcd",
        "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\n"
        "WIDTH 2\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 2\nDATA ascii\nnan nan nan\n"
        "nan 1 nan\n");
  write("negative.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [0.1, -0.1, 0.1]\n");
  write("cloud.xyz", "0 0 0\n");
  write("misspelt.yaml", "sector: {radius: 0.4, hieght: 0.7}\n");
  write("words.yaml", "views: ten\n");
  write("nan_view.yaml", "initial_view: {position: [.nan, 0.3, 1.4]}\n");
  write("time_limit.yaml", "time_limit_s: -1\n");
  const std::string tiny = "name: tiny\nplants: [{seed: 0}]\nyaws_deg: [0]\nviews: 2\n"
                           "studies:\n  - name: main\n    planners:\n";
  write("tiny.yaml", tiny + "      - {type: random}\n");
  write("yaw.yaml", "name: yaw\nplants: [{seed: 0}]\nyaws_deg: [0, 1e19]\nstudies:\n"
                    "  - name: main\n    planners: [{type: random}]\n");
  write("grid8.yaml", "sector: {rows: 2, cols: 4}\n");
  write("unknown_key.yaml", tiny + "      - {type: nbv, atention: leaf-nodes}\n");
  write("garbage.yaml", "studies: [unclosed\n");
  write("self_alias.yaml", "sector: &s {radius: 0.4, rows: [*s]}\n");
  write("deep.yaml", "sector: " + std::string(40, '[') + std::string(40, ']') + "\n");
  write("twice.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [0.1, 0.1, 0.1]\n"
                      "    size: [1, 1, 1]\n");
  std::string laughs =
      tiny + "      - {type: random}\nx0: &x0 [a, a, a, a, a, a, a, a]\n";
  for (int i = 1; i < 9; ++i)
    laughs += "x" + std::to_string(i) + ": &x" + std::to_string(i) + " [*x" +
              std::to_string(i - 1) + ", *x" + std::to_string(i - 1) + ", *x" +
              std::to_string(i - 1) + ", *x" + std::to_string(i - 1) + ", *x" +
              std::to_string(i - 1) + ", *x" + std::to_string(i - 1) + ", *x" +
              std::to_string(i - 1) + ", *x" + std::to_string(i - 1) + "]\n";
  write("laughs.yaml", laughs);
  fs::create_directories(path("dir.yaml"));
  ASSERT_EQ(::mkfifo(path("fifo.yaml").c_str(), 0600), 0);

  // A frames folder as `capture` writes it (one 320 x 240 frame; the pose on line 3 of
  // groundtruth.txt, the frame on line 3 of depth.txt), its map, and copies of the
  // folder with one defect each.
  ASSERT_EQ(
      run("capture --plant 1 --intrinsics l515-320 --frames-out " + path("good")).code,
      0);
  ASSERT_EQ(run("integrate " + path("good") + " -o " + path("good.ot")).code, 0);
  const auto copy = [&](const std::string& name) {
    fs::copy(path("good"), path(name), fs::copy_options::recursive);
    return dir_ / name;
  };
  const std::string png = "depth/000000.png";
  fs::remove(copy("nocamera") / "camera.yaml");
  editFile(copy("nomatrix") / "camera.yaml", [](std::string& text) {
    const auto from = text.find("camera_matrix:"), to = text.find("distortion_model:");
    ASSERT_LT(from, to);
    text.erase(from, to - from);
  });
  editFile(copy("wordwidth") / "camera.yaml",
           replacing("image_width: 320", "image_width: wide"));
  editFile(copy("wordmatrix") / "camera.yaml", [](std::string& text) {
    const auto fx = text.find("  data: [") + 9; // camera_matrix's, the first
    text.replace(fx, text.find(',', fx) - fx, "fx");
  });
  editFile(copy("wrongsize") / "camera.yaml",
           replacing("image_width: 320", "image_width: 640"));
  std::ofstream(copy("grey8") / png, std::ios::binary) << pngBytes(320, 240, 8, 0);
  std::ofstream(copy("colour") / png, std::ios::binary) << pngBytes(320, 240, 8, 2);
  std::ofstream(copy("colour16") / png, std::ios::binary) << pngBytes(320, 240, 16, 2);
  // The same encoder's 16-bit grey PNG is read: the two above fail for their format only.
  std::ofstream(copy("grey16") / png, std::ios::binary) << pngBytes(320, 240, 16, 0);
  EXPECT_EQ(run("integrate " + path("grey16") + " -o " + path("grey16.ot")).code, 0);
  editFile(copy("truncated") / png, [](std::string& b) { b.resize(b.size() / 2); });
  editFile(copy("cutheader") / png, [](std::string& b) { b.resize(40); });
  editFile(copy("nopng") / "depth.txt", replacing(png, "depth/000009.png"));
  editLastLine(copy("pose6") / "groundtruth.txt", [](auto& f) { f.resize(6); });
  editLastLine(copy("pose9") / "groundtruth.txt", [](auto& f) { f.push_back("1"); });
  editLastLine(copy("posenan") / "groundtruth.txt", [](auto& f) { f.at(3) = "nan"; });
  editLastLine(copy("poseinf") / "groundtruth.txt", [](auto& f) { f.at(7) = "-inf"; });
  editLastLine(copy("zeroquat") / "groundtruth.txt",
               [](auto& f) { std::fill(f.begin() + 4, f.end(), "0"); });
  editLastLine(copy("nopose") / "groundtruth.txt", [](auto& f) { f.at(0) = "0.021000"; });
  editFile(copy("scale0") / "camera.yaml",
           replacing("depth_scale: 1000", "depth_scale: 0"));
  editFile(copy("scaleneg") / "camera.yaml",
           replacing("depth_scale: 1000", "depth_scale: -5"));
  editFile(copy("distorted") / "camera.yaml",
           replacing("data: [0, 0, 0, 0, 0]", "data: [0.1, 0, 0, 0, 0]"));
  fs::create_directories(path("empty"));
  write("notamap.ot", "# not a map\n");
  write("notamap.bt", "# not a map\n");
  // Maps by hand: 8 occupied leaves under the root (2 bytes of .bt data); a .ot whose
  // root is its one node, occupied (log-odds 1.0f); resolutions out of range; a NaN.
  const std::string bt = "# Octomap OcTree binary file\nid OcTree\n";
  const std::string ot = "# Octomap OcTree file\nid OcTree\n";
  write("root_leaves.bt", bt + "size 9\nres 0.003\ndata\n\xaa\xaa");
  write("root.ot", ot + "res 0.005\ndata\n" + std::string("\0\0\x80\x3f\0", 5));
  write("tiny_res.bt", bt + "res 1e-300\ndata\n\xaa\xaa");
  write("huge_res.bt", bt + "res 1e300\ndata\n\xaa\xaa");
  write("nan_res.ot", ot + "res nan\ndata\n" + std::string("\0\0\x80\x3f\0", 5));
  write("word_res.ot", ot + "res fine\ndata\n" + std::string("\0\0\x80\x3f\0", 5));
  write("nan_node.ot",
        ot + "res 0.01\ndata\n" + std::string("\0\0\0\0\x01\0\0\xc0\x7f\0", 10));
  write("flat.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [0.1, 0, 0.1]\n");
  write("point.yaml", "boxes:\n  - center: [0, 0, 0]\n    size: [1, 1, 1]\n"
                      "  - center: [1, 0, 1]\n    size: [0, 0, 0]\n");
  fs::copy_file(path("good.ot"), path("cut.ot"));
  editFile(path("cut.ot"), [](std::string& b) { b.resize(2000); }); // in its data

  std::size_t cases = 0;
  for (const BadCall& call : kBadCalls) {
    std::string args = call.args, needle = call.needle;
    for (std::string* text : {&args, &needle})
      for (const auto& [mark, value] :
           {std::pair<std::string, std::string>{"{d}", path("")},
            {"{f}", kFixtures + "/"}})
        for (auto at = text->find(mark); at != std::string::npos; at = text->find(mark))
          text->replace(at, mark.size() + 1, value); // "{d}/" -> "<dir>/"
    SCOPED_TRACE("plantnbv " + args);
    expectOneLineError(run(args), call.code, needle);
    ++cases;
  }
  EXPECT_GE(cases, 30u);
}

TEST_F(CliTest, DamagedCloudsAndMapsAreOurOneLineWithoutLibraryChatter)
{
  // Good clouds and maps, then a family of damaged copies of each: cut at points in the
  // header and the data, and header lines changed. Each is read by `eval` (clouds and
  // maps as geometry) or `plan --map`: read whole (exit 0, nothing on stderr), or
  // refused in one line of ours that names the file: never PCL's or OctoMap's lines.
  ASSERT_EQ(run("sample --mesh " + kFixtures +
                "/plant_like.ply --points 500 --labels -o " + path("s.pcd"))
                .code,
            0);
  ASSERT_EQ(run("sample --mesh " + kFixtures + "/plant_like.ply --points 500 -o " +
                path("s.ply"))
                .code,
            0);
  std::string ascii =
      "# .PCD v0.7\nVERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\n"
      "COUNT 1 1 1\nWIDTH 6\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 6\n"
      "DATA ascii\n";
  for (int i = 0; i < 6; ++i)
    ascii += std::to_string(0.01 * i) + " 0.02 " + std::to_string(1.0 - 0.01 * i) + "\n";
  write("t.pcd", ascii);
  ASSERT_EQ(run("capture --plant 1 --intrinsics l515-320 --frames-out " + path("f")).code,
            0);
  for (const std::string map : {"m.bt", "m.ot"})
    ASSERT_EQ(run("integrate " + path("f") + " -o " + path(map)).code, 0);

  struct Edit {
    std::string from, to; ///< a header text and what replaces it
  };
  const std::vector<std::pair<std::string, std::vector<Edit>>> originals = {
      {"s.pcd",
       {{"FIELDS x y z label", "FIELDS x y z"},
        {"SIZE 4 4 4 4", "SIZE 4 4 3 4"},
        {"TYPE F F F U", "TYPE F F F Q"},
        {"COUNT 1 1 1 1", "COUNT 1 1 0 1"},
        {"WIDTH 500", "WIDTH 501"},
        {"POINTS 500", "POINTS 5000000"},
        {"DATA binary", "DATA binary_compressed"},
        {"DATA binary", "DATA"}}},
      {"t.pcd",
       {{"FIELDS x y z", "FIELDS x y z w"},
        {"POINTS 6", "POINTS 7"},
        {"WIDTH 6", "WIDTH six"},
        {"DATA ascii", "DATA text"},
        {"0.02 1.0", "0.02"}}},
      {"s.ply",
       {{"element vertex 500", "element vertex 501"},
        {"element vertex 500", "element vertex -1"},
        {"property float x", "property quad x"},
        {"binary_little_endian", "binary_middle_endian"},
        {"ply", "plx"}}},
      {"m.bt",
       {{"id OcTree", "id ColorOcTree"},
        {"res ", "res x"},
        {"size ", "size 1"},
        {"data\n", "dat\n"},
        {"# Octomap", "# Octomip"}}},
      {"m.ot",
       {{"id OcTree", "id OcTreeStamped"},
        {"res ", "res -"},
        {"size ", "size 9"},
        {"data\n", ""}}},
  };
  std::size_t refused = 0, read = 0;
  for (const auto& [name, edits] : originals) {
    const std::string good = slurp(path(name));
    std::vector<std::string> damaged;
    // The header ends with the line of its last keyword.
    const bool map = name.back() == 't';
    std::size_t header = good.find(map                  ? "\ndata\n"
                                   : name.back() == 'y' ? "end_header"
                                                        : "DATA");
    ASSERT_NE(header, std::string::npos) << name;
    header = good.find('\n', header + 1) + 1;
    for (const std::size_t at : {header / 2, header + 2, header + 12,
                                 (header + good.size()) / 2, good.size() - 1})
      damaged.push_back(good.substr(0, at));
    for (const Edit& e : edits) {
      const std::size_t at = good.find(e.from);
      ASSERT_NE(at, std::string::npos) << name << ": " << e.from;
      damaged.push_back(good.substr(0, at) + e.to + good.substr(at + e.from.size()));
    }
    for (std::size_t k = 0; k < damaged.size(); ++k) {
      const std::string file = path("d" + std::to_string(k) + "_" + name);
      std::ofstream(file, std::ios::binary) << damaged[k];
      for (const std::string& args :
           {"eval --reference " + file + " --reconstruction " + file,
            map ? "plan --map " + file : std::string()}) {
        if (args.empty())
          continue;
        SCOPED_TRACE("plantnbv " + args);
        const ToolRun r = run(args);
        if (r.code == 0)
          EXPECT_EQ(r.err, "");
        else
          expectOneLineError(r, 1, "d" + std::to_string(k) + "_" + name);
        ++(r.code == 0 ? read : refused);
      }
    }
  }
  EXPECT_GE(refused, 60u) << read << " read whole";
}
