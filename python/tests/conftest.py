"""Shared fixtures of the Python module's tests: the command-line tool of the same build (for
results the module must reproduce exactly), the bundled table and random directions."""
import json
import os
import pathlib
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]
BUNDLED_TABLE = REPO / "data" / "cc_ibiza_sunset_rgb.bsdf"


class Cli:
    """The `brdffit` executable of this build."""

    def __init__(self, path):
        self.path = path

    def __call__(self, *args):
        return subprocess.run([self.path, *map(str, args)], capture_output=True, text=True)

    def json(self, *args):
        """The parsed JSON a successful command prints."""
        done = self(*args)
        assert done.returncode == 0, done.stderr
        return json.loads(done.stdout)

    def error(self, *args):
        """The message a failing command prints, without the 'brdffit: error: ' prefix."""
        done = self(*args)
        assert done.returncode != 0, done.stdout
        return done.stderr.strip().removeprefix("brdffit: error: ")


@pytest.fixture(scope="session")
def cli():
    """The CLI named by BRDFFIT_CLI (set by build/python/pytest.sh)."""
    path = os.environ.get("BRDFFIT_CLI")
    if not path or not os.path.exists(path):
        if os.environ.get("CI"):  # any non-empty value, as CI services set it
            pytest.fail("BRDFFIT_CLI does not name the brdffit executable (run build/python/pytest.sh)")
        pytest.skip("BRDFFIT_CLI not set: run the tests with build/python/pytest.sh")
    return Cli(path)


@pytest.fixture(scope="session")
def bundled_table():
    assert BUNDLED_TABLE.exists(), f"{BUNDLED_TABLE} is part of the repository"
    return str(BUNDLED_TABLE)


def hemisphere_directions(rng, n, max_theta_deg=80.0):
    """n unit directions above the horizon, uniform in solid angle up to max_theta_deg."""
    z = rng.uniform(np.cos(np.radians(max_theta_deg)), 1.0, n)
    phi = rng.uniform(0.0, 2 * np.pi, n)
    r = np.sqrt(1.0 - z * z)
    return np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=1)
