import mujoco
import pytest

import mjtether as mt


def new_spec(timestep: float) -> mujoco.MjSpec:
    spec = mujoco.MjSpec()
    spec.option.timestep = timestep
    spec.option.integrator = mujoco.mjtIntegrator.mjINT_IMPLICITFAST
    return spec


@pytest.fixture
def spec_factory():
    return new_spec


@pytest.fixture(autouse=True)
def _no_leaked_providers():
    """Every test must close its simulations (the passive callback is process-wide)."""
    before = mt.dispatch.active_count()
    yield
    assert mt.dispatch.active_count() == before, "a test left a simulation registered"
