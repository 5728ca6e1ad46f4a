"""Setting a tracking run up: :func:`~collisionkit.transport.tracking.track`'s arguments checked and turned into arrays.

The checks of single arguments (integers, tolerances, the start positions,
the direction, the times, the profile coordinate) and the kernel's field
arguments (:mod:`collisionkit._kernels.transport.tracking`). The checks of
the run's choices (methods, ion drift) stay with :func:`track`.
"""

from __future__ import annotations

import math

import numpy as np

from ..._kernels.transport import derived_field
from ..._kernels.transport.tracking import codes as _c
from .device import Device
from .fields import CoaxialField, ParallelPlateField, _finite, _vector


def integer(name, value, low, high=None):
    """``value`` as an int, if it is an integer (not a bool) in [low, high] (no upper end if ``high`` is None).

    Parameters
    ----------
    name : str
        The argument's name, for the messages.
    value : int
        The value given.
    low, high : int
        The allowed range (``high`` None: no upper end).

    Returns
    -------
    int

    Raises
    ------
    TypeError
        If ``value`` is not an integer.
    ValueError
        If it is out of range.

    Examples
    --------
    >>> integer("groups", np.int64(4), 2, 1024)
    4
    >>> integer("groups", 1, 2, 1024)
    Traceback (most recent call last):
    ...
    ValueError: groups must be in [2, 1024]; got 1
    """
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)):
        raise TypeError(f"{name} must be an integer; got {value!r}")
    if value < low or (high is not None and value > high):
        allowed = f">= {low}" if high is None else f"in [{low}, {high}]"
        raise ValueError(f"{name} must be {allowed}; got {value}")
    return int(value)


def bounded(name, value):
    """``value`` as a float, if it is a tolerance in (0, 0.1].

    Parameters
    ----------
    name : str
        The argument's name, for the messages.
    value : float
        The value given.

    Returns
    -------
    float

    Examples
    --------
    >>> bounded("tolerance", 1e-6)
    1e-06
    >>> bounded("tolerance", 0.2)
    Traceback (most recent call last):
    ...
    ValueError: tolerance must be in (0, 0.1]; got 0.2
    """
    value = _finite(name, value, 0.0, low_open=True)
    if value > 0.1:
        raise ValueError(f"{name} must be in (0, 0.1]; got {value:g}")
    return value


def start_positions(position, primaries, geometry) -> np.ndarray:
    """The start of every primary (m): one position for all, or one row each, inside ``geometry``.

    Parameters
    ----------
    position : 3 numbers or (primaries x 3) array
        The start position(s) given.
    primaries : int
        Primaries of the run.
    geometry : Geometry
        The device's geometry.

    Returns
    -------
    ndarray
        ``(primaries, 3)``, C-contiguous.

    Raises
    ------
    ValueError
        If the shape is wrong, a coordinate not finite, or a start outside the volume.

    Examples
    --------
    >>> from collisionkit.transport.tracking import parallel_plate_geometry
    >>> start_positions((0, 0, 5e-5), 2, parallel_plate_geometry(1e-4)).shape
    (2, 3)
    """
    array = np.asarray(position, dtype=float)
    if array.shape == (3,):
        array = np.broadcast_to(array, (primaries, 3))
    if array.shape != (primaries, 3) or not np.all(np.isfinite(array)):
        raise ValueError(f"position must be three numbers (m) or one row of three per primary ({primaries}); "
                         f"got shape {np.shape(position)}")
    outside = ~geometry.contains(array)
    if outside.any():
        raise ValueError(f"position {array[np.argmax(outside)].tolist()} (m) lies outside the device's volume")
    return np.ascontiguousarray(array)


def unit_direction(direction) -> np.ndarray:
    """The primaries' direction as a unit vector, or zeros (isotropic) for None.

    Parameters
    ----------
    direction : 3 numbers or None
        The direction given (any length but zero).

    Returns
    -------
    ndarray

    Examples
    --------
    >>> unit_direction((0, 0, 2)).tolist(), unit_direction(None).tolist()
    ([0.0, 0.0, 1.0], [0.0, 0.0, 0.0])
    """
    if direction is None:
        return np.zeros(3)
    direction = _vector("direction", direction)
    if not np.linalg.norm(direction) > 0:
        raise ValueError("direction must not be zero")
    return direction / np.linalg.norm(direction)


def checked_times(device: Device, sample_times, time_limit) -> tuple[np.ndarray, float]:
    """The sample times and the time limit (s) of a run: by default the last sample time, else none (inf).

    Parameters
    ----------
    device : Device
        The device (an unbounded one needs a finite time limit).
    sample_times : sequence or None
        Times at which the moments are sampled (finite, >= 0, increasing).
    time_limit : float or None
        The time at which particles still moving end.

    Returns
    -------
    tuple
        ``(sample times, time limit)``.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> from collisionkit.transport.tracking import UniformField
    >>> device = Device(maxwell_model(1e-13, mass=1e-29), 1e23, 0.0, UniformField((0, 0, 1e3)))
    >>> checked_times(device, [1e-10, 2e-10], None)[1]
    2e-10
    """
    sample_times = np.zeros(0) if sample_times is None else np.asarray(sample_times, dtype=float).reshape(-1)
    if sample_times.size and (not np.all(np.isfinite(sample_times)) or np.any(np.diff(sample_times) <= 0)
                              or sample_times[0] < 0):
        raise ValueError("sample_times must be finite, >= 0 and increasing (s)")
    if time_limit is None:
        time_limit = float(sample_times[-1]) if sample_times.size else math.inf
    time_limit = _finite("time_limit (s)", time_limit, 0.0, low_open=True) if math.isfinite(time_limit) else math.inf
    if not device.geometry.surfaces and not math.isfinite(time_limit):
        raise ValueError("an unbounded device (no surfaces) needs time_limit or sample_times: nothing else ends a "
                         "particle")
    return sample_times, time_limit


def profile_setting(device: Device, profile, bins):
    """(kind code, parameters, edges, name, bins) of the profile coordinate.

    Parameters
    ----------
    device : Device
        The device: its field gives the default coordinate (z between plates,
        the radius in a counter; none otherwise).
    profile : tuple or None
        ``("z" or "radius", low, high)``, or None for the default.
    bins : int
        Bins of the profiles.

    Returns
    -------
    tuple

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> profile_setting(device, None, 4)[3:]
    ('z', 4)
    """
    if profile is None:
        if isinstance(device.electric, ParallelPlateField):
            profile = ("z", 0.0, device.electric.gap)
        elif isinstance(device.electric, CoaxialField):
            profile = ("radius", device.electric.wire_radius, device.electric.cathode_radius)
        else:
            return 0, np.zeros(4), np.zeros(1), "none", 0
    name, low, high = profile
    if name not in ("z", "radius") or not (math.isfinite(low) and math.isfinite(high) and high > low):
        raise ValueError(f"profile must be ('z' or 'radius', low, high) with high > low (m); got {profile!r}")
    axis = device.electric.axis if isinstance(device.electric, CoaxialField) else (0.0, 0.0)
    code = _c.PROFILE_Z if name == "z" else _c.PROFILE_RADIUS
    return code, np.array([*axis, low, high]), np.linspace(low, high, bins + 1), name, bins


def field_arrays(device: Device):
    """The kernel's field arguments: E, B, weighting, surfaces, exact flag and the uniform-field record.

    Parameters
    ----------
    device : Device
        The device whose fields and surfaces the kernel follows.

    Returns
    -------
    tuple
        ``(kernel arguments, exact, electric field, magnetic field)``: exact
        when both fields are uniform (the motion between collisions is then
        exact); an absent field is a zero uniform one.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> field_arrays(device)[1]
    True
    """
    from .fields import UniformField
    from .magnetic import UniformMagneticField

    electric = device.electric or UniformField((0.0, 0.0, 0.0))
    magnetic = device.magnetic or UniformMagneticField((0.0, 0.0, 0.0))
    e_arrays = electric.arrays() if device.electric is not None else (_c.E_NONE, *electric.arrays()[1:])
    e_arrays = (*e_arrays[:4], electric.blocks(), e_arrays[4])  # the kernel takes the map's local bounds too
    b_arrays = magnetic.arrays() if device.magnetic is not None else (_c.B_NONE, *magnetic.arrays()[1:])
    exact = electric.is_uniform() and magnetic.is_uniform()
    w_kind, w_par = device.weighting.arrays() if device.weighting is not None else (_c.W_NONE,
                                                                                     np.zeros(_c.FIELD_PARAMETERS))
    return (*e_arrays, *b_arrays, w_kind, w_par, device.geometry.table(), exact), exact, electric, magnetic


def kernel_fields(device: Device, method_code: int, charge: float, mass: float) -> tuple:
    """The kernel's field arguments (:func:`field_arrays`) followed by the record of the exact uniform-field flight.

    Parameters
    ----------
    device : Device
        The device.
    method_code : int
        The collision method's code (:data:`~collisionkit.transport.tracking.METHODS`).
    charge, mass : float
        The tracked particle (C, kg).

    Returns
    -------
    tuple

    Raises
    ------
    ValueError
        If the null-collision method is asked for in a user's field with no bound.

    Examples
    --------
    >>> from collisionkit.transport import maxwell_model
    >>> device = Device.parallel_plate(maxwell_model(1e-13, mass=1e-29), 1e-4, 10.0, density=1e23)
    >>> kernel_fields(device, _c.NULL_COLLISION, -1.602176634e-19, 9.1093837e-31)[-1].shape
    (13,)
    """
    field_args, exact, electric, _ = field_arrays(device)
    if method_code == _c.NULL_COLLISION and not exact and not math.isfinite(electric.bound()) and \
            field_args[0] == _c.E_USER:
        raise ValueError("the null-collision method needs a bound of the field: give UserField(..., max_field=) or "
                         "use method='path-length'")
    flight = np.zeros(13)
    if exact:
        acceleration = charge * (electric.uniform_value() if device.electric is not None else np.zeros(3)) / mass
        omega = charge * (device.magnetic.uniform_value() if device.magnetic is not None else np.zeros(3)) / mass
        flight = derived_field(acceleration, omega)
    return (*field_args, flight)
