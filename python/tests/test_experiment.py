"""Trials and campaigns from Python: the same steps as the tool's with the same seed."""

import csv
import json
import math

import numpy as np
import pytest

import plantnbv as pn


def steps_csv(path):
    with open(path) as f:
        rows = list(csv.DictReader(f))
    return {k: [float(r[k]) if r[k] != "" else math.nan for r in rows] for k in rows[0]}


@pytest.mark.parametrize("planner, attention, extra", [
    ("nbv", "main_stem", []),
    ("predefined", "whole_plant", ["--pattern", "2"]),
])
def test_a_trial_equals_reconstruct_with_the_same_seed(placed, cli, tmp_path, planner,
                                                       attention, extra):
    cli("reconstruct", "--plant", 3, "--planner", planner, "--attention", attention,
        "--views", 3, "--seed", 11, *extra, "-o", tmp_path / "tool")
    tool = steps_csv(tmp_path / "tool" / "steps.csv")
    pattern = int(extra[1]) if extra else None
    seen = []
    result = pn.run_trial(placed, planner=planner, attention=attention, pattern=pattern,
                          views=3, seed=11, map_out=tmp_path / "ours.bt",
                          progress=lambda step: seen.append(step["view"]))
    ours = result.columns()
    assert seen == [0, 1, 2] and len(result) == 3
    assert list(ours) == list(tool)
    for column, values in tool.items():
        if column.endswith("_ms"):
            continue
        np.testing.assert_array_equal(ours[column], values, err_msg=column)
    assert (tmp_path / "ours.bt").read_bytes() == (tmp_path / "tool" / "map.bt").read_bytes()
    np.testing.assert_array_equal(result.reconstruction,
                                  pn.read_cloud(tmp_path / "tool" / "reconstruction.pcd"))
    assert result.level_names == ["whole_plant", "main_stem", "leaf_nodes", "fruit"]
    np.testing.assert_array_equal(result.f1_curve(attention), tool[attention + "_f1"])
    step = result.steps[1]
    assert step["scores"][attention]["f1"] == tool[attention + "_f1"][1]
    assert step["organ_recall"]["stem"] == tool["recall_stem"][1] > 0.0
    assert step["pose"].shape == (7,) and step["candidates"] in (9, 27)


def test_the_sensor_options_are_reconstructs(placed, cli, tmp_path):
    cli("reconstruct", "--plant", 3, "--views", 2, "--seed", 5, "--intrinsics", "l515-320",
        "--noise", "--no-background", "-o", tmp_path / "tool")
    tool = steps_csv(tmp_path / "tool" / "steps.csv")
    ours = pn.run_trial(placed, views=2, seed=5, camera=pn.CameraIntrinsics.l515("320x240"),
                        noise=True, background=False).columns()
    for column, values in tool.items():
        if not column.endswith("_ms"):
            np.testing.assert_array_equal(ours[column], values, err_msg=column)
    plain = pn.run_trial(placed, views=2, seed=5).columns()
    assert not np.array_equal(plain["whole_plant_f1"], ours["whole_plant_f1"])


def test_a_row_and_a_sector_radius_are_reconstructs(placed, cli, tmp_path):
    cli("reconstruct", "--plant", 3, "--views", 2, "--seed", 5, "--row-spacing", 0.25,
        "--sector-radius", 0.5, "-o", tmp_path / "tool")
    tool = steps_csv(tmp_path / "tool" / "steps.csv")
    ours = pn.run_trial(placed, views=2, seed=5, row_spacing_m=0.25,
                        sector_radius_m=0.5).columns()
    for column, values in tool.items():
        if not column.endswith("_ms"):
            np.testing.assert_array_equal(ours[column], values, err_msg=column)
    # The second view lies on the 0.5 m sector around the base (1, 0, 0.8).
    assert np.hypot(ours["x"][1] - 1.0, ours["y"][1]) == pytest.approx(0.5, abs=1e-6)


def test_a_noisy_roi_source_is_reconstructs(placed, cli, tmp_path):
    cli("reconstruct", "--plant", 3, "--views", 2, "--seed", 5, "--attention", "leaf_nodes",
        "--roi-source", "noisy", "--roi-sigma", 0.02, "-o", tmp_path / "tool")
    tool = steps_csv(tmp_path / "tool" / "steps.csv")
    noisy = pn.run_trial(placed, attention="leaf_nodes", views=2, seed=5, roi_source="noisy",
                         roi_sigma=0.02)
    ours = noisy.columns()
    for column, values in tool.items():
        if not column.endswith("_ms"):
            np.testing.assert_array_equal(ours[column], values, err_msg=column)
    oracle = pn.run_trial(placed, attention="leaf_nodes", views=2, seed=5)
    truth = [b.center for b in oracle.attended_roi.boxes]
    moved = [b.center for b in noisy.attended_roi.boxes]
    assert len(truth) == len(moved) > 0
    assert all(not np.array_equal(t, m) for t, m in zip(truth, moved))
    with pytest.raises(ValueError, match="roi_sigma 0.01: only the noisy ROI source"):
        pn.run_trial(placed, views=2, roi_sigma=0.01)


def test_a_detections_roi_source_is_reconstructs(placed, cli, tmp_path):
    cli("reconstruct", "--plant", 3, "--views", 2, "--seed", 5, "--attention", "leaf_nodes",
        "--roi-source", "detections", "--detector-recall", 0.8, "--detector-box-jitter", 3,
        "--detector-mask-dilation", 2, "--detector-masks", "false",
        "--detections-explore-views", 0, "-o", tmp_path / "tool")
    tool = steps_csv(tmp_path / "tool" / "steps.csv")
    ours = pn.run_trial(placed, attention="leaf_nodes", views=2, seed=5,
                        roi_source="detections", detector_recall=0.8,
                        detector_box_jitter=3, detector_mask_dilation=2,
                        detector_masks=False, detections_explore_views=0)
    for column, values in tool.items():
        if not column.endswith("_ms"):
            np.testing.assert_array_equal(ours.columns()[column], values, err_msg=column)
    assert len(ours.attended_roi.boxes) > 0
    assert all(b.name.startswith("leaf_node_") for b in ours.attended_roi.boxes)
    with pytest.raises(ValueError, match="detector_mask_dilation 2: only the detections"):
        pn.run_trial(placed, views=2, detector_mask_dilation=2)
    with pytest.raises(ValueError, match="detector_box_jitter 3: the fusion back-projects"):
        pn.run_trial(placed, views=2, roi_source="detections", detector_box_jitter=3)


def test_a_progress_callback_that_raises_stops_the_trial(placed):
    def stop(step):
        raise RuntimeError("enough at view %d" % step["view"])

    with pytest.raises(RuntimeError, match="enough at view 0"):
        pn.run_trial(placed, views=3, progress=stop)


def test_views_to_reach_and_unknown_levels(placed):
    result = pn.run_trial(placed, planner="random", views=2, seed=1)
    curve = result.f1_curve("whole_plant")
    assert result.views_to_reach("whole_plant", 0.0) == 1
    assert result.views_to_reach("whole_plant", 2.0) is None
    assert pn.views_to_reach(list(curve), 0.0) == 1
    with pytest.raises(ValueError, match="level: expected one of whole_plant"):
        result.f1_curve("leaves")


CAMPAIGN = """\
name: tiny
seed: 7
plants:
  - seeds: [0]
yaws_deg: [0, 90]
views: 2
candidates: 9
resolution: 0.005
repetitions: 1
levels: [whole_plant, main_stem]
studies:
  - name: main
    planners:
      - {type: nbv, attention: main-stem}
      - {type: random}
"""


def test_a_campaign_runs_resumes_and_reports(tmp_path, cli):
    file = tmp_path / "tiny.yaml"
    file.write_text(CAMPAIGN)
    events = []
    status = pn.run_campaign(file, tmp_path / "run", workers=2,
                             progress=lambda p: events.append(p["event"]))
    assert status == {"total": 4, "done": 4, "failed": 0, "missing": 0, "foreign": 0,
                      "failed_ids": [],
                      "failed_errors": []}
    assert events[0] == "started" and events.count("finished") == 4
    assert pn.campaign_status(tmp_path / "run") == status
    timing = pn.campaign_timing(tmp_path / "run")
    assert sum(row["trials"] for row in timing) == 4
    assert sum(row["share"] for row in timing) == pytest.approx(1.0)
    trials = [json.loads(f.read_text()) for f in (tmp_path / "run" / "trials").glob("*.json")]
    for row in timing:  # the means of the planner's trial files
        files = [t for t in trials if t["spec"]["planner"] == row["planner"]]
        assert row["trials"] == len(files)
        assert row["total_ms"] == pytest.approx(
            sum(f["total_ms"] for f in files) / len(files))
        assert row["insert_ms"] == pytest.approx(
            sum(v["insert_ms"] for f in files for v in f["views"]) / len(files))
    again = []
    pn.run_campaign(file, tmp_path / "run", progress=lambda p: again.append(p))
    assert again[0]["skipped"] == 4 and again[0]["to_run"] == 0
    written = pn.campaign_report(tmp_path / "run")
    assert [p.name for p in written] == ["curves.csv", "summary.md"]
    assert all(p.is_file() for p in written)
    tool = tmp_path / "tool-report"
    cli("campaign", "report", tmp_path / "run", "-o", tool, "--no-figures")
    assert (tool / "curves.csv").read_text() == written[0].read_text()
