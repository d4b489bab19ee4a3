from pathlib import Path

import numpy as np
import pytest

from slicelab.samples import random_motion

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"


@pytest.fixture(scope="session")
def data_dir() -> Path:
    return DATA


def random_rotation(rng: np.random.Generator) -> np.ndarray:
    """A uniformly random proper rotation as a 4x4 matrix."""
    return random_motion(rng)
