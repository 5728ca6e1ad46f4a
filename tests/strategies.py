"""Hypothesis strategies for collision inputs."""

import numpy as np
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

masses = st.floats(1e-3, 1e3)
restitutions = st.floats(0.0, 1.0)
dimensions = st.sampled_from([1, 2, 3])


def components(bound):
    """Floats in [-bound, bound], zero or of magnitude > 1e-100 (squares stay normal)."""
    return st.floats(-bound, bound, allow_subnormal=False).filter(lambda x: x == 0 or abs(x) > 1e-100)


def vectors(dimension, bound=1e3):
    return hnp.arrays(np.float64, (dimension,), elements=components(bound))


@st.composite
def contacts(draw, dimension=None):
    """(m1, v1, m2, v2, normal, e) for one pair with a non-degenerate normal."""
    d = draw(dimensions) if dimension is None else dimension
    normal = draw(vectors(d, 10.0).filter(lambda n: np.linalg.norm(n) > 1e-3))
    return draw(masses), draw(vectors(d)), draw(masses), draw(vectors(d)), normal, draw(restitutions)
