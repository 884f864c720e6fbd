"""brdffit.models() and brdffit.eval(): the model library and vectorised evaluation."""
import math

import numpy as np
import pytest

import brdffit
from conftest import hemisphere_directions


def test_models_list_the_cli_models_with_their_parameters(cli):
    listed = cli.json("models", "--json")
    models = brdffit.models()
    assert [m.name for m in models] == [m["model"] for m in listed]
    for model, entry in zip(models, listed):
        assert model.summary == entry["summary"]
        assert model.has_brdf == entry["brdf"]
        assert [(p.name, p.channels, p.lower, p.upper, p.default, p.meaning, p.role, p.integer)
                for p in model.parameters] == \
               [(p["name"], p["channels"], p["lower"], p["upper"], p["default"], p["meaning"], p["role"], p["integer"])
                for p in entry["parameters"]]
        assert model.num_values == sum(p.channels for p in model.parameters)
        assert len(model.default_values()) == model.num_values


def test_lambert_is_albedo_over_pi_times_cos_theta_i():
    light = np.array([[0.0, 0.0, 1.0], [math.sin(1.0), 0.0, math.cos(1.0)], [0.3, -0.4, -0.2]])
    view = np.array([[0.0, 0.0, 1.0], [0.0, 0.6, 0.8], [0.0, 0.0, 1.0]])
    shaded, f = brdffit.eval("lambert", {"albedo": (0.2, 0.5, 0.8)}, light, view)
    albedo = np.array([0.2, 0.5, 0.8])
    assert shaded.shape == (3, 3) and f.shape == (3, 3)
    np.testing.assert_allclose(f, np.tile(albedo / math.pi, (3, 1)), rtol=1e-15)
    np.testing.assert_allclose(shaded[0], albedo / math.pi, rtol=1e-15)
    np.testing.assert_allclose(shaded[1], albedo / math.pi * math.cos(1.0), rtol=1e-14)
    np.testing.assert_array_equal(shaded[2], 0.0)  # light below the horizon


def test_eval_matches_the_cli_at_each_pair_of_directions(cli):
    rng = np.random.default_rng(3)
    light, view = hemisphere_directions(rng, 4), hemisphere_directions(rng, 4)
    params = {"albedo": (0.1, 0.2, 0.3), "roughness": 0.3, "f0": 0.5}
    shaded, f = brdffit.eval("ggx", params, light * 2.0, view)  # directions need not be unit
    for i in range(4):
        out = cli.json("eval", "-m", "ggx", "--param", "albedo=0.1,0.2,0.3", "--param", "roughness=0.3",
                       "--param", "f0=0.5", "--light", ",".join(map(repr, light[i])),
                       "--view", ",".join(map(repr, view[i])), "--json")
        np.testing.assert_allclose(shaded[i], out["shade"], rtol=1e-12)
        np.testing.assert_allclose(f[i], out["brdf"], rtol=1e-12)


def test_params_as_flat_values_dict_or_defaults_agree():
    model = brdffit.model("ggx")
    light, view = np.array([0.2, 0.1, 0.9]), np.array([-0.3, 0.0, 0.8])
    values = model.default_values()
    values[model.parameters[0].channels] = 0.25  # roughness follows the albedo's three values
    by_values = brdffit.eval(model, values, light, view)[0]
    by_dict = brdffit.eval("ggx", {"roughness": 0.25}, light, view)[0]
    np.testing.assert_array_equal(by_values, by_dict)
    assert by_values.shape == (3,)
    assert not np.array_equal(brdffit.eval("ggx", None, light, view)[0], by_dict)


def test_one_direction_broadcasts_over_many():
    rng = np.random.default_rng(5)
    light = hemisphere_directions(rng, 50)
    view = np.array([0.0, 0.0, 1.0])
    shaded, _ = brdffit.eval("ggx", None, light, view)
    assert shaded.shape == (50, 3)
    for i in (0, 17, 49):
        np.testing.assert_array_equal(shaded[i], brdffit.eval("ggx", None, light[i], view)[0])


def test_models_without_a_brdf_return_none_for_f():
    stylised = [m for m in brdffit.models() if not m.has_brdf]
    assert stylised, "the library has stylised shaders"
    shaded, f = brdffit.eval(stylised[0], None, np.array([[0, 0, 1.0]]), np.array([[0, 0, 1.0]]))
    assert f is None and shaded.shape == (1, 3)


def test_bad_parameters_raise_the_cli_messages(cli):
    light = view = np.array([0.0, 0.0, 1.0])
    cases = [("ggx", {"roughness": 2.0}, ["--param", "roughness=2"]),
             ("ggx", {"shininess": 1.0}, ["--param", "shininess=1"]),
             ("ggx", {"f0": (0.1, 0.2)}, ["--param", "f0=0.1,0.2"]),
             ("no-such-model", None, [])]
    for model, params, cli_args in cases:
        with pytest.raises(brdffit.Error) as raised:
            brdffit.eval(model, params, light, view)
        assert str(raised.value) == cli.error("eval", "-m", model, *cli_args, "--light", "0,0,1", "--view", "0,0,1")


def test_bad_directions_and_value_counts_raise_errors():
    with pytest.raises(brdffit.Error, match=r"light: expected an \(N, 3\) array .* got shape \(4, 2\)"):
        brdffit.eval("lambert", None, np.zeros((4, 2)), np.array([0, 0, 1.0]))
    with pytest.raises(brdffit.Error, match="view: direction 1 is the zero vector"):
        brdffit.eval("lambert", None, np.array([0, 0, 1.0]), np.array([[0, 0, 1.0], [0, 0, 0]]))
    with pytest.raises(brdffit.Error, match="view: direction 0 is not finite"):
        brdffit.eval("lambert", None, np.array([0, 0, 1.0]), np.array([0, np.nan, 1.0]))
    with pytest.raises(brdffit.Error, match="light and view: 2 and 3 directions"):
        brdffit.eval("lambert", None, np.ones((2, 3)), np.ones((3, 3)))
    with pytest.raises(brdffit.Error, match="params: 2 values given, model ggx has 7"):
        brdffit.eval("ggx", [0.5, 0.5], np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))
    with pytest.raises(TypeError):
        brdffit.eval("ggx", "roughness=0.5", np.array([0, 0, 1.0]), np.array([0, 0, 1.0]))
    assert issubclass(brdffit.Error, ValueError)


def test_everything_public_has_a_docstring():
    public = [getattr(brdffit, name) for name in dir(brdffit) if not name.startswith("_")]
    for thing in public:
        assert thing.__doc__ and len(thing.__doc__) > 20, thing
    assert "Ctrl-C" in brdffit.fit.__doc__ and "metric" in brdffit.fit.__doc__
