"""brdffit.read, samples, fit and score: recovery of known parameters, equality with the CLI
on the bundled table, and errors."""
import _thread
import json
import math
import os
import pathlib
import signal

import numpy as np
import pytest

import brdffit
from conftest import hemisphere_directions

GGX_TRUTH = {"albedo": (0.30, 0.20, 0.10), "roughness": 0.35, "f0": (0.50, 0.60, 0.70)}


def ggx_samples(n=3000, seed=7):
    rng = np.random.default_rng(seed)
    light, view = hemisphere_directions(rng, n), hemisphere_directions(rng, n)
    shaded, _ = brdffit.eval("ggx", GGX_TRUTH, light, view)
    return light, view, shaded


def test_fit_recovers_known_ggx_parameters_from_arrays():
    light, view, shaded = ggx_samples()
    results = brdffit.fit(brdffit.samples(light, view, shaded), models=["lambert", "ggx"])
    assert [r.model for r in results] == ["lambert", "ggx"]
    ggx = results["ggx"]
    assert results.best is ggx and ggx.ok and ggx.status == "ok" and ggx.verdict == "good"
    assert ggx.parameters["roughness"].value == pytest.approx(0.35, rel=1e-4)
    for name in ("albedo", "f0"):
        np.testing.assert_allclose(ggx.parameters[name].value, GGX_TRUTH[name], rtol=1e-4)
        assert isinstance(ggx.parameters[name].value, tuple) and len(ggx.parameters[name].stddev) == 3
    assert isinstance(ggx.parameters["roughness"].value, float)
    assert ggx.metrics["cosine"] < 1e-6 < results["lambert"].metrics["cosine"]
    # The fitted values evaluate to the data again.
    np.testing.assert_allclose(brdffit.eval("ggx", ggx, light, view)[0], shaded, atol=1e-5)


def test_on_result_sees_each_model():
    light, view, shaded = ggx_samples(500)
    seen = []
    results = brdffit.fit(brdffit.samples(light, view, shaded), models="lambert,ggx",
                          on_result=lambda r: seen.append((r.model, r.ok)))
    assert seen == [("lambert", True), ("ggx", True)] and len(results) == 2

    def stop(result):
        raise RuntimeError(f"stop after {result.model}")
    with pytest.raises(RuntimeError, match="stop after lambert"):
        brdffit.fit(brdffit.samples(light, view, shaded), models="lambert,ggx", on_result=stop)


def test_per_channel_fit_recovers_a_roughness_per_channel():
    rng = np.random.default_rng(11)
    light, view = hemisphere_directions(rng, 3000), hemisphere_directions(rng, 3000)
    roughness = (0.2, 0.4, 0.6)
    shaded = np.empty((3000, 3))
    for c in range(3):
        shaded[:, c] = brdffit.eval("ggx", dict(GGX_TRUTH, roughness=roughness[c]), light, view)[0][:, c]
    ggx = brdffit.fit(brdffit.samples(light, view, shaded), models="ggx", per_channel=True)["ggx"]
    np.testing.assert_allclose(ggx.parameters["roughness"].value, roughness, rtol=1e-3)
    assert len(ggx.channel_values) == 3
    np.testing.assert_allclose(brdffit.eval("ggx", ggx, light, view)[0], shaded, atol=1e-5)


def test_weights_choose_which_samples_count():
    # Half the samples say albedo 0.2, half 0.6; weights 3:1 make the weighted fit 0.3.
    rng = np.random.default_rng(2)
    light, view = hemisphere_directions(rng, 400), hemisphere_directions(rng, 400)
    albedo = np.where(np.arange(400) < 200, 0.2, 0.6)[:, None] * np.ones(3)
    shaded = albedo / math.pi * light[:, 2:3]
    weight = np.where(np.arange(400) < 200, 3.0, 1.0) * light[:, 2] ** -2  # cancels cos² in the residual
    lambert = brdffit.fit(brdffit.samples(light, view, shaded, weight), models="lambert")["lambert"]
    np.testing.assert_allclose(lambert.parameters["albedo"].value, (0.3, 0.3, 0.3), rtol=1e-9)


def test_fit_of_the_bundled_table_equals_the_cli(cli, bundled_table, tmp_path):
    out = tmp_path / "cli.json"
    done = cli("fit", bundled_table, "--models", "lambert,ggx", "--out", out)
    assert done.returncode == 0, done.stderr
    expected = json.loads(out.read_text())
    results = brdffit.fit(brdffit.read(bundled_table), models="lambert,ggx")
    document = results.document()
    for doc in (expected, document):
        for model in doc["models"]:
            model.pop("seconds")
    assert document == expected
    assert [r.as_dict()["parameters"] for r in results] == [m["parameters"] for m in expected["models"]]
    # save() writes the same document, readable by the CLI's commands.
    results.save(tmp_path / "py.json")
    assert json.loads((tmp_path / "py.json").read_text())["models"][1]["values"] == expected["models"][1]["values"]


def test_score_equals_the_cli_and_the_fit_metrics(cli, bundled_table):
    table = brdffit.read(bundled_table)
    expected = cli.json("score", bundled_table, "-m", "ggx", "--param", "roughness=0.3", "--param", "f0=0.2", "--json")
    ours = brdffit.score(table, "ggx", {"roughness": 0.3, "f0": 0.2})
    assert {name: ours[name] for name in expected["metrics"]} == pytest.approx(expected["metrics"], rel=1e-12)
    light, view, shaded = ggx_samples(500)
    samples = brdffit.samples(light, view, shaded)
    fitted = brdffit.fit(samples, models="ggx")["ggx"]
    assert brdffit.score(samples, fitted) == pytest.approx(fitted.metrics, rel=1e-12)
    assert brdffit.score(samples, "ggx", GGX_TRUTH)["cosine"] == pytest.approx(0.0, abs=1e-15)


def test_read_gives_the_samples_the_cli_fits_as_arrays(bundled_table):
    table = brdffit.read(bundled_table)
    n = len(table)
    assert table.light.shape == table.view.shape == table.rgb.shape == (n, 3) and table.weight.shape == (n,)
    np.testing.assert_allclose(np.linalg.norm(table.light, axis=1), 1.0, rtol=1e-12)
    assert (table.light[:, 2] > 0).all() and (table.weight > 0).all()
    assert table.info["format"] == "rgl" and table.path == bundled_table
    # A sample's value is f·cosθi, and the table's look-up gives f at the same directions.
    picks = np.arange(0, n, max(1, n // 200))
    f = table.lookup(table.light[picks], table.view[picks])
    np.testing.assert_allclose(f * table.light[picks, 2:3], table.rgb[picks], rtol=1e-6, atol=1e-9)
    with pytest.raises(ValueError):
        table.rgb[0, 0] = 1.0  # views of the library's samples are read-only
    subset = brdffit.read(pathlib.Path(bundled_table), max_samples=300, seed=4)
    assert len(subset) == 300
    np.testing.assert_array_equal(subset.rgb, brdffit.read(bundled_table, max_samples=300, seed=4).rgb)
    assert len(brdffit.read(bundled_table, max_angle=60)) < n


def test_samples_round_trip_through_arrays(bundled_table):
    table = brdffit.read(bundled_table, max_samples=1000)
    copy = brdffit.samples(table.light, table.view, table.rgb, table.weight)
    for field in ("light", "view", "rgb", "weight"):
        np.testing.assert_allclose(getattr(copy, field), getattr(table, field), rtol=1e-15)
    assert copy.source == "arrays" and copy.weighting == "given"


def test_ctrl_c_stops_a_fit_midway_with_keyboard_interrupt():
    # The uncancelled fit reports each solver iteration (of ggx, and of Lambert, the baseline of
    # the verdict), more than three. A Ctrl-C at the third, once the solver has demonstrably
    # started, stops it there: not one iteration more.
    samples = brdffit.samples(*ggx_samples())
    seen = []
    brdffit.fit(samples, models="ggx", on_iteration=lambda model, iteration: seen.append((model, iteration)))
    assert len(seen) > 3 and {model for model, _ in seen} == {"lambert", "ggx"} and seen[0][1] == 0

    def ctrl_c_at_the_third(model, iteration):
        seen.append((model, iteration))
        if len(seen) == 3:
            _thread.interrupt_main()

    seen.clear()
    # Python's own SIGINT handler, which a shell does not install for a job it starts in the
    # background (SIGINT ignored there, and interrupt_main then does nothing).
    previous = signal.signal(signal.SIGINT, signal.default_int_handler)
    try:
        with pytest.raises(KeyboardInterrupt):
            brdffit.fit(samples, models="ggx", on_iteration=ctrl_c_at_the_third)
    finally:
        signal.signal(signal.SIGINT, previous)
    assert len(seen) == 3
    assert brdffit.fit(samples, models="lambert")["lambert"].ok  # usable afterwards


def test_an_exception_from_on_iteration_stops_the_fit_and_propagates():
    samples = brdffit.samples(*ggx_samples())
    seen = []

    def fail_at_the_second(model, iteration):
        seen.append(iteration)
        if len(seen) == 2:
            raise ValueError("enough")

    with pytest.raises(ValueError, match="enough"):
        brdffit.fit(samples, models="ggx", on_iteration=fail_at_the_second)
    assert len(seen) == 2


def test_bad_files_raise_the_cli_messages(cli, bundled_table, tmp_path):
    truncated = tmp_path / "truncated.bsdf"
    truncated.write_bytes(open(bundled_table, "rb").read()[:1000])
    unknown = tmp_path / "table.txt"
    unknown.write_text("hello")
    for path in (tmp_path / "missing.binary", truncated, unknown):
        with pytest.raises(brdffit.Error) as raised:
            brdffit.read(str(path))
        assert str(raised.value) == cli.error("fit", path, "--models", "lambert")
        assert str(path) in str(raised.value)


def test_csv_samples_read_but_have_no_look_up(tmp_path):
    csv = tmp_path / "s.csv"
    csv.write_text("lx,ly,lz,vx,vy,vz,r,g,b\n0,0,1,0,0,1,0.1,0.2,0.3\n0.6,0,0.8,0,0,1,0.1,0.2,0.3\n")
    table = brdffit.read(str(csv))
    np.testing.assert_allclose(table.rgb[1], np.array([0.1, 0.2, 0.3]) * 0.8)
    with pytest.raises(brdffit.Error, match="s.csv: a CSV of samples is not a table"):
        table.lookup(np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))


def test_bad_options_and_arrays_raise_errors(cli, bundled_table):
    light, view, shaded = ggx_samples(10)
    samples = brdffit.samples(light, view, shaded)
    with pytest.raises(brdffit.Error, match=r"metric: unknown metric 'rms' \(cosine, log, relative, l2\)"):
        brdffit.fit(samples, metric="rms")
    with pytest.raises(brdffit.Error, match="loss: unknown loss 'l1'"):
        brdffit.fit(samples, loss="l1")
    with pytest.raises(brdffit.Error) as raised:
        brdffit.fit(samples, models="lambert,nope")
    assert str(raised.value) == cli.error("fit", bundled_table, "--models", "lambert,nope")
    with pytest.raises(brdffit.Error, match="max_angle"):
        brdffit.read(bundled_table, max_angle=95)
    bad = shaded.copy()
    bad[3, 1] = np.nan
    with pytest.raises(brdffit.Error, match="arrays: sample 3: the value is not finite"):
        brdffit.samples(light, view, bad)
    with pytest.raises(brdffit.Error, match="arrays: sample 2: negative reflectance"):
        brdffit.samples(light, view, np.where(np.arange(10)[:, None] == 2, -1.0, shaded))
    with pytest.raises(brdffit.Error, match="sample 0: the weight is negative"):
        brdffit.samples(light, view, shaded, -np.ones(10))
    below = light.copy()
    below[5, 2] = -0.1
    with pytest.raises(brdffit.Error, match="sample 5: a direction lies on or below the horizon"):
        brdffit.samples(below, view, shaded)
    with pytest.raises(brdffit.Error, match=r"rgb: expected shape \(10, 3\)"):
        brdffit.samples(light, view, shaded[:5])
    with pytest.raises(brdffit.Error, match=r"weight: expected shape \(10,\)"):
        brdffit.samples(light, view, shaded, np.ones(3))
    with pytest.raises(TypeError):
        brdffit.fit(42)
    with pytest.raises(brdffit.Error, match="params: a fit of lambert, not of ggx"):
        brdffit.eval("ggx", brdffit.fit(samples, models="lambert")[0], light, view)


def test_save_refuses_its_input_and_names_are_bytes(tmp_path):
    # A CSV of a Lambert material (albedo 0.5) under a name that is not UTF-8, as os.listdir gives it.
    rng = np.random.default_rng(3)
    light, view = hemisphere_directions(rng, 200), hemisphere_directions(rng, 200)
    rows = ["lx,ly,lz,vx,vy,vz,r,g,b"] + [
        ",".join(map(str, [*l, *v, 0.5 / math.pi, 0.5 / math.pi, 0.5 / math.pi])) for l, v in zip(light, view)
    ]
    name = os.fsdecode(b"m\xff.csv")
    table = tmp_path / name
    table.write_text("\n".join(rows) + "\n")
    results = brdffit.fit(brdffit.read(table), models="lambert")
    assert results.input == str(table)  # round-trips through os.fsdecode
    assert "\\xff" in repr(results)
    # save() makes the check every writer makes: never over the table the results came from.
    with pytest.raises(brdffit.Error, match="the output is the input"):
        results.save(table)
    assert table.read_text().startswith("lx,")
    results.save(tmp_path / "doc.json")
    document = json.loads((tmp_path / "doc.json").read_text())
    assert bytes.fromhex(document["input"]["path_bytes"]) == os.fsencode(table)


def test_fix_holds_a_known_parameter():
    truth = {"baseColor": (0.6, 0.3, 0.2), "metallic": 0.0, "roughness": 0.4}
    rng = np.random.default_rng(5)
    light, view = hemisphere_directions(rng, 1500), hemisphere_directions(rng, 1500)
    shaded, _ = brdffit.eval("gltf", truth, light, view)
    data = brdffit.samples(light, view, shaded)
    gltf = brdffit.fit(data, models="gltf", fix={"metallic": 0})["gltf"]
    metallic = gltf.parameters["metallic"]
    assert metallic.fixed and metallic.value == 0.0 and math.isnan(metallic.stddev)
    assert not gltf.parameters["roughness"].fixed
    assert gltf.parameters["roughness"].value == pytest.approx(0.4, rel=1e-4)
    with pytest.raises(brdffit.Error, match="--fix metallic=2: outside the gltf model's bounds"):
        brdffit.fit(data, models="gltf", fix={"metallic": 2})
