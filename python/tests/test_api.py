"""platefield's Python functions give the CLI's numbers; errors name the value."""

import csv
import io
import json

import numpy as np
import pytest

import platefield


def test_design_sink_equals_cli(root, cli, scratch):
    # Both methods run (auto: sequence and a synthesis with small budgets),
    # and the CLI flags are the keywords.
    target = root / "targets" / "sink.json"
    budget = dict(synth_evaluations=20, polish_plays=4)
    py = platefield.design(target, "auto", quiet=True, **budget)
    text = cli("design", target, "--method", "auto", "--synth-evaluations", 20,
               "--polish-plays", 4, "--json", "--quiet", "--out", scratch / "cli")
    assert py == json.loads(text)
    # A JSON float is read back as the same float: same dict, same numbers.
    assert json.dumps(py) == json.dumps(json.loads(text))
    assert py["target"] == "sink"
    assert py["played"]["method"] in ("sequence", "synthesize")


def test_design_from_dict_equals_path(root):
    target = root / "targets" / "sink.json"
    as_dict = json.loads(target.read_text())
    assert platefield.design(as_dict, "sequence", quiet=True) == platefield.design(
        target, "sequence", quiet=True
    )


def test_design_writes_only_when_asked(root, scratch):
    platefield.design(root / "targets" / "sink.json", "sequence", quiet=True)
    assert not (scratch / "results").exists()
    platefield.design(root / "targets" / "sink.json", "sequence", quiet=True, out=scratch / "o")
    assert (scratch / "o" / "sink" / "schedule.json").is_file()


def test_misspelt_option_names_it():
    with pytest.raises(TypeError, match=r"'polsh_plays' \(did you mean 'polish_plays'\?\)"):
        platefield.design({"name": "x"}, "auto", polsh_plays=3)


def test_misspelt_target_key_names_its_path(root):
    t = json.loads((root / "targets" / "sink.json").read_text())
    t["field"]["strenght"] = 1.0
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.design(t, "sequence", quiet=True)
    assert e.value.path == "target.field.strenght" and e.value.file is None
    assert "unknown field" in e.value.message


def test_misspelt_key_in_a_file_names_file_and_path(root, scratch):
    t = json.loads((root / "targets" / "sink.json").read_text())
    t["grid"]["nn"] = [9, 9]
    (scratch / "bad.json").write_text(json.dumps(t))
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.design(scratch / "bad.json", "sequence", quiet=True)
    assert e.value.path == "target.grid.nn" and "unknown field" in e.value.message
    assert e.value.file == str(scratch / "bad.json")
    assert str(e.value).startswith(f"{scratch / 'bad.json'}: target.grid.nn: ")


def test_option_out_of_range_names_it(root):
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.design(root / "targets" / "sink.json", mode="budget", budget=1.5)
    assert e.value.path == "budget"
    assert "(0, 1)" in e.value.message


def test_bad_schedule_names_its_path():
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.export({"segments": [], "wieght": 1}, 1000.0)
    assert e.value.path == "schedule.wieght" and e.value.file is None
    assert "unknown field" in e.value.message


def test_export_equals_cli_csv(root, cli, scratch):
    s = platefield.design(root / "targets" / "sink.json", "sequence", quiet=True, out=scratch)
    a = platefield.export(s, 5000)
    text = cli("export", scratch / "sink" / "schedule.json", "--rate", 5000)
    # The CSV opens with comment lines stating the frame, reference point and peaks.
    rows = list(csv.reader(l for l in io.StringIO(text) if not l.startswith("#")))
    assert rows[0][0] == "t_s"
    b = np.array(rows[1:], dtype=float)
    assert a.shape == b.shape and a.shape[1] == 7 and a.shape[0] > 100
    # The CSV prints t to 1e-9 s and the signals to 13 significant digits.
    assert np.max(np.abs(a[:, 0] - b[:, 0])) <= 5e-10
    scale = np.max(np.abs(b[:, 1:]), axis=0) + 1e-300
    assert np.max(np.abs(a[:, 1:] - b[:, 1:]) / scale) <= 1e-11
    # Exported from the file and from the dict: the same array.
    assert np.array_equal(a, platefield.export(scratch / "sink" / "schedule.json", 5000))


def test_field_equals_cli(root, cli):
    scene = root / "targets" / "scenes" / "linesink.json"
    f = platefield.field(scene, quiet=True)
    j = json.loads(cli("field", scene, "--json", "--quiet"))
    nx, ny = 11, 11
    assert f["fx"].shape == (ny, nx) and f["x"].shape == (nx,) and f["y"].shape == (ny,)
    assert f["kind"] == "force"
    assert np.allclose(f["x"], np.linspace(-0.04, 0.04, nx), rtol=0, atol=1e-15)
    # The CLI prints the same arrays, exactly (JSON floats round-trip).
    for key in ("fx", "fy", "valid", "x", "y"):
        assert np.array_equal(np.array(j[key]), f[key]), key
    # The screw rotates about the y axis: the field does not change along y
    # and has no y component; it squeezes parts onto the line near x = 0.
    assert np.all(f["valid"])
    assert np.allclose(f["fx"], f["fx"][0], rtol=0, atol=1e-12)
    assert np.max(np.abs(f["fy"])) <= 1e-12
    assert np.all(f["fx"][:, 0] > 0) and np.all(f["fx"][:, -1] < 0)


def test_verify_equals_cli(root, cli, scratch):
    s = platefield.design(root / "targets" / "sink.json", "sequence", quiet=True, out=scratch)
    opts = dict(points=3, swarm=3, rect_poses=0, repetitions=1, quiet=True)
    py = platefield.verify(s, **opts)
    text = cli("verify", scratch / "sink" / "schedule.json", "--points", 3, "--swarm", 3,
               "--rect-poses", 0, "--repetitions", 1, "--quiet", "--json", "--out", scratch / "v")
    assert py == json.loads(text)
    assert py["model_check"]["points"] == 9


def test_options_become_the_cli_flags():
    from platefield._api import flags

    assert flags(dict(polish_plays=50, quiet=True, json=False, cycles=None, budget=0.1,
                      primitives=["LineSink", "Circle"], shift=[(-0.01, 0), (0, -0.02)])) == [
        "--polish-plays=50", "--quiet", "--budget=0.1", "--primitives=LineSink,Circle",
        "--shift=-0.01,0", "--shift=0,-0.02",
    ]


def test_primitives_option_restricts_the_design(root):
    s = platefield.design(root / "targets" / "sink.json", "sequence", quiet=True,
                          primitives=["LineSink", "Trans"])
    kinds = {seg["primitive"]["kind"] for seg in s["segments"]}
    assert kinds and kinds <= {"LineSink", "Trans"}


def test_default_design_of_sink_equals_the_shipped_result(root):
    # `platefield design targets/sink.json` (all defaults) wrote
    # results/sink/schedule.json; the package's default design is the same.
    shipped = json.loads((root / "results" / "sink" / "schedule.json").read_text())
    s = platefield.design(root / "targets" / "sink.json", quiet=True)
    assert s == shipped
    assert s["played"]["realised_strength"] > 0 and not s["played"]["poor"]


def test_poses_equals_cli(root, cli):
    part = root / "targets" / "parts" / "rectangle.json"
    source = root / "targets" / "ellipse.json"
    py = platefield.poses(part, source, drops=20)
    assert py == json.loads(cli("poses", part, source, "--drops", 20, "--json"))
    # From dicts: the same analysis.
    as_dicts = platefield.poses(json.loads(part.read_text()), json.loads(source.read_text()), drops=20)
    assert as_dicts == py
    # The rectangle on the elliptic sink (-0.3x, -y): stable with its long
    # side along x (0 deg or 180 deg), within 1 deg of the closed form.
    stable = [e["theta_deg"] for e in py["equilibria"] if e["stable"]]
    assert len(stable) == 2
    assert all(min(abs(t), abs(abs(t) - 180.0)) < 1.0 for t in stable), stable


def test_bad_part_names_its_path(root):
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.poses({"name": "x", "polygon": [[0, 0], [0.01, 0]]}, root / "targets" / "ellipse.json")
    assert e.value.path == "part.polygon"
    assert e.value.file is None
    assert "at least 3" in e.value.message


def test_export_returns_peaks_and_harmonics_as_the_cli(root, cli):
    # The peaks are the CSV header's, and --format harmonics' terms are the
    # same numbers as the CLI's harmonics CSV.
    s = root / "results" / "synthesized" / "sink" / "schedule.json"
    rows, peaks = platefield.export(s, 5000, peaks=True)
    assert np.array_equal(rows, platefield.export(s, 5000))
    text = cli("export", s, "--rate", 5000)
    line = next(l for l in text.splitlines() if l.startswith("#   acceleration:"))
    numbers = [float(x) for x in line.replace("[", ",").replace("]", ",").split(",")[1:]
               if x.strip() and not x.strip().startswith(("m/s", "rad"))]
    assert np.allclose(numbers, peaks["acceleration"], rtol=1e-6, atol=1e-12)
    assert set(peaks) == {"acceleration", "velocity", "stroke"}
    h = platefield.export(s, format="harmonics")
    assert h["terms"].shape[1] == 4 and h["period"] > 0
    table = [l for l in cli("export", s, "--format", "harmonics").splitlines()
             if l and not l.startswith("#")]
    assert len(table) - 1 == h["terms"].shape[0]
    with pytest.raises(ValueError, match='format must be "csv" or "harmonics"'):
        platefield.export(s, format="mat")


def test_design_friction_keyword_sets_the_targets_friction(root):
    target = root / "targets" / "sink.json"
    as_dict = json.loads(target.read_text())
    as_dict["friction"] = 0.45
    fast = dict(quiet=True, primitives=["LineSink"], rotation_step=90, no_cache=True)
    by_keyword = platefield.design(target, "sequence", friction=0.45, **fast)
    assert by_keyword == platefield.design(as_dict, "sequence", **fast)
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.design(target, "sequence", friction=0, **fast)
    assert e.value.path == "friction" and "frictionless" in str(e.value)


def test_package_ships_type_hints():
    import pathlib
    here = pathlib.Path(platefield.__file__).parent
    assert (here / "py.typed").is_file()
    stub = (here / "__init__.pyi").read_text()
    for name in platefield.__all__:
        assert name in stub, name


def test_design_model_auto_records_rungs_that_load_back(root):
    # design --model auto records its rung choice under "rungs", the rung
    # played being the schedule's settings.model; the package loads such a
    # schedule back: verify reads the record, and export plays the same
    # plate motion as the default design's (the model is not in the motion).
    target = root / "targets" / "sink.json"
    auto = platefield.design(target, "sequence", model="auto", quiet=True)
    plain = platefield.design(target, "sequence", quiet=True)
    assert "rungs" not in plain and plain["settings"]["model"]["coriolis"] is True
    assert auto["rungs"]["played"] == "paper+moving+centripetal+tilt"
    assert auto["settings"]["model"]["coriolis"] is False
    assert auto["segments"] == plain["segments"]
    assert np.array_equal(platefield.export(auto, 5000), platefield.export(plain, 5000))
    v = platefield.verify(auto, points=3, swarm=1, rect_poses=0, repetitions=1, quiet=True)
    assert v["recorded_rungs"] == auto["rungs"]
    bad = dict(auto, rungs=dict(auto["rungs"], played="cheap"))
    with pytest.raises(platefield.InvalidInput) as e:
        platefield.export(bad, 5000)
    assert e.value.path == "rungs.played" and "paper+moving" in e.value.message
