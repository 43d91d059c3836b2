// Every subcommand's bad arguments and files, as a table: each gives exit code 1 (bad
// input) or 2 (usage error) and one line on stderr that names what was wrong.

#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "cli_fixture.h"

using plantnbv::test::CliTest;
using plantnbv::test::expectOneLineError;
using plantnbv::test::kFixtures;

namespace {

struct BadCall {
  std::string args;   ///< "{d}" stands for the test's directory, "{f}" for the fixtures
  int code;           ///< 1 bad input, 2 usage error
  std::string needle; ///< what the message must name
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
    {"campaign run {d}/tiny.yaml -o {d}/c -j -1", 2, "--jobs"},
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
    // capture
    {"capture -o {d}/v.pcd", 1, "--plant"},
    {"capture --plant 1 --pose 1,2,3,0,0,0,0 -o {d}/v.pcd", 1, "quaternion"},
    {"capture --plant 1 --pose nan,2,3,0,0,0,1 -o {d}/v.pcd", 1, "--pose"},
    {"capture --plant 1 --intrinsics l516 -o {d}/v.pcd", 1, "l516"},
    {"capture --plant 1 --resolution -1 --map {d}/m.bt -o {d}/v.pcd", 1, "resolution"},
    {"capture --plant 1 -o {d}/v.xyz", 1, "v.xyz"},
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
};

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
  write("unknown_key.yaml", tiny + "      - {type: nbv, atention: leaf-nodes}\n");
  write("garbage.yaml", "studies: [unclosed\n");

  std::size_t cases = 0;
  for (const BadCall& call : kBadCalls) {
    std::string args = call.args;
    for (const auto& [mark, value] :
         {std::pair<std::string, std::string>{"{d}", path("")}, {"{f}", kFixtures + "/"}})
      for (auto at = args.find(mark); at != std::string::npos; at = args.find(mark))
        args.replace(at, mark.size() + 1, value); // "{d}/" -> "<dir>/"
    SCOPED_TRACE("plantnbv " + args);
    expectOneLineError(run(args), call.code, call.needle);
    ++cases;
  }
  EXPECT_GE(cases, 30u);
}
