"""Dynamic movement primitives: a demonstrated segment, or several merged, as a stable system.

    Times = (n,) float array, seconds, strictly increasing, any start, any spacing
    Poses = (n, 3) positions x y z (metres), or (n, 7) x y z qx qy qz qw (unit quaternions)
    DMP   = (duration, start, goal, weights (n_basis, dims), centers, widths, alpha_z, beta_z, alpha_x,
             start_velocity)

The paper represents each segment of a kinesthetic demonstration as a discrete DMP (Sec. II-C,
Ijspeert et al. 2013); merging the primitives of a merged action is its first future work
(Sec. V). Every pose dimension d gets its own transformation system; all share one canonical
system (phase x, from 1 down to exp(-alpha_x) = 0.01 at t = tau):

    tau * dz = alpha_z * (beta_z * (g - y) - z) + f(x) * scale      tau = duration
    tau * dy = z                                                     y(0) = y0, z(0) = tau * v0
    tau * dx = -alpha_x * x                                          x(t) = exp(-alpha_x t / tau)
    f(x)     = sum_i psi_i(x) w_i x / sum_i psi_i(x)                 psi_i = exp(-h_i (x - c_i)^2)

with scale = g - y0 (Ijspeert's spatial scaling), replaced by 1 where |g - y0| < 1e-6: a
dimension that does not move (often a quaternion component) keeps the same equations, its
forcing term simply unscaled. The centres c_i are spread evenly in time over [0, tau] (over
each segment, for a merged primitive). v0 is the demonstration's (smoothed) initial velocity:
starting the rollout the way the fitted forcing term assumes keeps a slow system (a long tau,
as in a merged primitive) from carrying a start-up error through the whole motion; to start
at rest instead, replace start_velocity by zeros (for a segment that began at rest, v0 is
small anyway).

Fitting smooths a copy of the demonstration (local quadratic fits in time, weighted by a
Gaussian over a few samples: a Savitzky-Golay filter whose window turns one-sided at the ends,
keeping the trend there instead of pulling the end samples towards the middle), takes start and
goal from its first and last samples, differentiates it with np.gradient over the real times,
and solves for the weights of all dimensions at once by least squares, with a small penalty on
the second differences of the forcing values across the bases (a few samples, fewer than the
bases, still fit: the bases they leave free interpolate their neighbours). Quaternions are
normalised and made sign-continuous first (the first with qw >= 0); each component is
otherwise an ordinary dimension, and rollout renormalises them. A rollout starts at (y0, v0)
and integrates the linear system exactly on a fine grid (the matrix exponential, the forcing
term linear between grid points), then reads the times asked for off cubic Hermite splines.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

Poses = np.ndarray
Times = np.ndarray

ALPHA_X = math.log(100.0)          # x(tau) = 0.01
SMOOTHING = 4.0                    # Gaussian kernel sigma, in samples
RIDGE = 1e-6                       # relative ridge term of the weight regression
_STILL = 1e-6                      # |g - y0| below this: the forcing term is not scaled
_GRID = 2000                       # integration steps per duration (at least 20 per basis)
_OVERLAP = 0.7                     # basis width relative to the spacing of the centres


@dataclass(frozen=True)
class DMP:
    """One discrete movement primitive per pose dimension, sharing a canonical system."""

    duration: float
    start: tuple[float, ...]
    goal: tuple[float, ...]
    weights: tuple[tuple[float, ...], ...]
    centers: tuple[float, ...]
    widths: tuple[float, ...]
    alpha_z: float = 25.0
    beta_z: float = 6.25
    alpha_x: float = ALPHA_X
    start_velocity: tuple[float, ...] = ()     # v0 per dimension, m/s; () is at rest

    def __post_init__(self) -> None:
        dims, n_basis = len(self.start), len(self.centers)
        if dims not in (3, 7) or len(self.goal) != dims:
            raise ValueError(f"a DMP has 3 or 7 dimensions, got start {len(self.start)} and goal {len(self.goal)}")
        if not self.start_velocity:
            object.__setattr__(self, "start_velocity", (0.0,) * dims)
        if len(self.start_velocity) != dims:
            raise ValueError(f"start_velocity needs {dims} values, got {len(self.start_velocity)}")
        if n_basis < 1 or len(self.widths) != n_basis or len(self.weights) != n_basis:
            raise ValueError(f"a DMP needs as many weights, centres and widths (>= 1), got "
                             f"{len(self.weights)}, {n_basis}, {len(self.widths)}")
        if any(len(row) != dims for row in self.weights):
            raise ValueError(f"every row of weights needs {dims} values, one per dimension")
        numbers = (self.duration, self.alpha_z, self.beta_z, self.alpha_x, *self.start, *self.goal,
                   *self.start_velocity,
                   *self.centers, *self.widths, *(w for row in self.weights for w in row))
        if not all(math.isfinite(v) for v in numbers):
            raise ValueError("a DMP's numbers must all be finite")
        if min(self.duration, self.alpha_z, self.beta_z, self.alpha_x, *self.widths) <= 0:
            raise ValueError("duration, alpha_z, beta_z, alpha_x and widths must be positive")

    @property
    def dims(self) -> int:
        return len(self.start)

    @property
    def n_basis(self) -> int:
        return len(self.centers)


@dataclass(frozen=True)
class Error:
    """How far a rollout is from a demonstration, over the demonstration's samples."""

    rms: float                 # metres, RMS of the position error
    max: float                 # metres
    final: float               # metres, last reproduced to last demonstrated position
    angle_rms: float | None    # radians, RMS of the orientation error; None for positions only


# -- input ---------------------------------------------------------------------------------

def _check(times, poses) -> tuple[np.ndarray, np.ndarray]:
    """The demonstration as float arrays, or a ValueError saying what is wrong with it."""
    t = np.asarray(times, dtype=float)
    p = np.asarray(poses, dtype=float)
    if t.ndim != 1:
        raise ValueError(f"times must be a 1-D array, got shape {t.shape}")
    if p.ndim != 2 or p.shape[1] not in (3, 7):
        raise ValueError(f"poses must be an (n, 3) or (n, 7) array, got shape {p.shape}")
    if len(t) != len(p):
        raise ValueError(f"{len(t)} times but {len(p)} poses")
    if len(t) < 2:
        raise ValueError(f"a trajectory needs at least 2 samples, got {len(t)}")
    if not (np.all(np.isfinite(t)) and np.all(np.isfinite(p))):
        raise ValueError("times and poses must be finite (no NaN or inf)")
    if np.any(np.diff(t) <= 0):
        raise ValueError("times must be strictly increasing")
    if not t[-1] - t[0] > 0:
        raise ValueError("a trajectory needs a positive duration")
    if p.shape[1] == 7:
        p = p.copy()
        p[:, 3:] = _continuous(p[:, 3:])
    return t, p


def _continuous(q: np.ndarray) -> np.ndarray:
    """Unit quaternions, the first with qw >= 0, each on the side of its predecessor."""
    norms = np.linalg.norm(q, axis=1)
    if np.any(norms < 1e-9):
        raise ValueError("a quaternion has zero norm")
    q = q / norms[:, None]
    signs = np.ones(len(q))
    lead = q[0, [3, 0, 1, 2]]
    signs[0] = -1.0 if lead[np.flatnonzero(lead)[0]] < 0 else 1.0
    dots = np.einsum("ij,ij->i", q[1:], q[:-1])
    signs[1:] = np.where(dots < 0, -1.0, 1.0)
    return q * np.cumprod(signs)[:, None]


def _smooth(t: np.ndarray, y: np.ndarray, sigma: float, degree: int = 2) -> np.ndarray:
    """y smoothed by local quadratic fits in time, weighted by a Gaussian of `sigma` samples.

    Near the ends the window is one-sided and the fitted polynomial keeps the trend, so the
    ends are denoised without being pulled towards the middle. Fitting in time, not sample
    index, keeps uneven steps unbiased. The kernel spans at most half of a short trajectory.
    """
    n = len(y)
    sigma = min(sigma, (n - 1) / 6)            # a short segment: never average over most of it
    radius = min(int(math.ceil(3 * sigma)), n - 1)
    if sigma <= 0 or radius < 1:
        return y.copy()
    degree = min(degree, radius)
    step = (t[-1] - t[0]) / (n - 1)
    exponents = np.arange(degree + 1)
    gram = np.zeros((n, degree + 1, degree + 1))
    rhs = np.zeros((n, degree + 1, y.shape[1]))
    for k in range(-radius, radius + 1):
        i = np.arange(max(0, -k), min(n, n - k))
        weight = math.exp(-0.5 * (k / sigma) ** 2)
        powers = ((t[i + k] - t[i]) / step)[:, None] ** exponents          # (m, degree + 1)
        gram[i] += weight * powers[:, :, None] * powers[:, None, :]
        rhs[i] += weight * powers[:, :, None] * y[i + k][:, None, :]
    gram += 1e-12 * gram[:, :1, :1] * np.eye(degree + 1)
    return np.linalg.solve(gram, rhs)[:, 0, :]


# -- the system ----------------------------------------------------------------------------

def _basis(fractions: np.ndarray, alpha_x: float) -> tuple[np.ndarray, np.ndarray]:
    """Centres at the given fractions of the duration, and widths that make neighbours overlap."""
    centers = np.exp(-alpha_x * fractions)
    if len(centers) == 1:
        return centers, np.array([1.0])
    gaps = np.abs(np.diff(centers))
    gaps = (np.append(gaps, gaps[-1]) + np.insert(gaps, 0, gaps[0])) / 2
    return centers, 1.0 / (_OVERLAP * gaps) ** 2


def _cells(edges: np.ndarray, per_cell: int) -> np.ndarray:
    """per_cell fractions spread evenly over each interval between consecutive edges."""
    spread = (np.arange(per_cell) + 0.5) / per_cell
    return np.concatenate([a + (b - a) * spread for a, b in zip(edges[:-1], edges[1:])])


def _features(x: np.ndarray, centers: np.ndarray, widths: np.ndarray) -> np.ndarray:
    """psi_i(x) x / sum_j psi_j(x) for every phase in x: (len(x), n_basis)."""
    log_psi = -widths[None, :] * (x[:, None] - centers[None, :]) ** 2
    log_psi -= log_psi.max(axis=1, keepdims=True)
    psi = np.exp(log_psi)
    return psi * (x / psi.sum(axis=1))[:, None]


def _scale(start: np.ndarray, goal: np.ndarray) -> np.ndarray:
    """g - y0, or 1 for a dimension that does not move."""
    span = goal - start
    return np.where(np.abs(span) < _STILL, 1.0, span)


def _expm(a: np.ndarray) -> np.ndarray:
    """The matrix exponential of a small matrix (scaling and squaring, Taylor series)."""
    norm = np.abs(a).sum(axis=1).max()
    squarings = max(0, int(math.ceil(math.log2(norm))) + 1) if norm > 0.5 else 0
    a = a / 2 ** squarings
    result, term = np.eye(len(a)), np.eye(len(a))
    for k in range(1, 20):
        term = term @ a / k
        result = result + term
    for _ in range(squarings):
        result = result @ result
    return result


def fit(times, poses, n_basis: int = 30, smoothing: float = SMOOTHING) -> DMP:
    """Learn a DMP from one demonstrated trajectory."""
    t, p = _check(times, poses)
    return _fit(t, p, np.array([0.0, 1.0]), n_basis, smoothing)


def _fit(t: np.ndarray, p: np.ndarray, edges: np.ndarray, per_cell: int, smoothing: float) -> DMP:
    """The DMP of a checked trajectory, per_cell bases between consecutive edges (fractions of
    its duration)."""
    if int(per_cell) != per_cell or per_cell < 1:
        raise ValueError(f"the number of bases must be a positive integer, got {per_cell}")
    if not (math.isfinite(smoothing) and smoothing >= 0):
        raise ValueError(f"smoothing must be a non-negative number of samples, got {smoothing}")
    # A basis cannot represent detail finer than its own width: where a basis covers many samples
    # (a slow demonstration), smooth over a quarter of them, so noise does not dominate the
    # accelerations the forcing term is fitted to.
    per_basis = len(t) / (int(per_cell) * (len(edges) - 1))
    y = _smooth(t, p, max(smoothing, per_basis / 4) if smoothing > 0 else 0.0)
    tau = float(t[-1] - t[0])
    order = 2 if len(t) > 2 else 1
    yd = np.gradient(y, t, axis=0, edge_order=order)
    ydd = np.gradient(yd, t, axis=0, edge_order=order)
    start, goal = y[0], y[-1]
    alpha_z, beta_z, alpha_x = 25.0, 6.25, ALPHA_X
    target = (tau ** 2 * ydd - alpha_z * (beta_z * (goal - y) - tau * yd)) / _scale(start, goal)
    centers, widths = _basis(_cells(edges, int(per_cell)), alpha_x)
    phi = _features(np.exp(-alpha_x * (t - t[0]) / tau), centers, widths) / centers
    weights = _regress(phi, target) / centers[:, None]
    return DMP(duration=tau, start=_floats(start), goal=_floats(goal),
               weights=tuple(_floats(row) for row in weights),
               centers=_floats(centers), widths=_floats(widths),
               alpha_z=alpha_z, beta_z=beta_z, alpha_x=alpha_x, start_velocity=_floats(yd[0]))


def _regress(phi: np.ndarray, target: np.ndarray) -> np.ndarray:
    """Least-squares weights, regularised towards a forcing term smooth across the bases.

    Columns are scaled by their centre, so the unknowns are forcing values near each basis;
    the penalty on their second differences fills the bases no sample reaches by
    interpolation instead of pulling them to zero.
    """
    n_basis = phi.shape[1]
    gram = phi.T @ phi
    order = min(2, n_basis - 1)
    d = np.diff(np.eye(n_basis), n=order, axis=0)
    penalty = d.T @ d + 1e-3 * np.eye(n_basis)
    level = max(float(np.mean(np.diag(gram))), 1e-300)
    return np.linalg.solve(gram + RIDGE * level * penalty, phi.T @ target)


def _floats(values) -> tuple[float, ...]:
    return tuple(float(v) for v in values)


def rollout(dmp: DMP, times=None, samples: int | None = None) -> Poses:
    """Integrate the DMP from its start towards its goal, at the given times (relative to
    times[0]) or at `samples` evenly spaced instants over its duration (100 when neither is
    given); quaternions come out renormalised."""
    if times is not None and samples is not None:
        raise ValueError("give times or samples, not both")
    if times is None:
        samples = 100 if samples is None else samples
        if int(samples) != samples or samples < 1:
            raise ValueError(f"samples must be a positive integer, got {samples}")
        at = np.linspace(0.0, dmp.duration, int(samples))
    else:
        t = np.asarray(times, dtype=float)
        if t.ndim != 1 or len(t) < 1 or not np.all(np.isfinite(t)) or np.any(np.diff(t) <= 0):
            raise ValueError("times must be a non-empty 1-D array of finite, strictly increasing values")
        at = t - t[0]
    tau = dmp.duration
    start, goal = np.array(dmp.start), np.array(dmp.goal)
    weights = np.array(dmp.weights)
    centers, widths = np.array(dmp.centers), np.array(dmp.widths)
    per_duration = max(_GRID, 20 * dmp.n_basis)
    steps = max(1, int(math.ceil(at[-1] / tau * per_duration)))
    h = at[-1] / steps if at[-1] > 0 else tau / per_duration
    grid = h * np.arange(steps + 1)
    force = _features(np.exp(-dmp.alpha_x * grid / tau), centers, widths) @ weights
    force *= _scale(start, goal)
    # state v = (y - g, z): dv/dt = A v + B u, u = f * scale, linear between grid points
    a = np.array([[0.0, 1.0], [-dmp.alpha_z * dmp.beta_z, -dmp.alpha_z]]) / tau
    b = np.array([0.0, 1.0 / tau])
    big = np.zeros((4, 4))
    big[:2, :2], big[:2, 2], big[2, 3] = a * h, b * h, 1.0
    e = _expm(big)
    ad, b0, b1 = e[:2, :2], e[:2, 2] - e[:2, 3], e[:2, 3]
    states = np.empty((steps + 1, 2, dmp.dims))
    v = np.stack([start - goal, tau * np.array(dmp.start_velocity)])
    states[0] = v
    for k in range(steps):
        v = ad @ v + np.outer(b0, force[k]) + np.outer(b1, force[k + 1])
        states[k + 1] = v
    y, dy = states[:, 0] + goal, states[:, 1] / tau
    y[0] = start                            # exactly, not (start - goal) + goal
    # cubic Hermite interpolation between grid points
    i = np.minimum((at / h).astype(int), steps - 1)
    s = np.clip((at - grid[i]) / h, 0.0, 1.0)[:, None]
    h00, h10 = 2 * s ** 3 - 3 * s ** 2 + 1, s ** 3 - 2 * s ** 2 + s
    h01, h11 = -2 * s ** 3 + 3 * s ** 2, s ** 3 - s ** 2
    out = h00 * y[i] + h10 * h * dy[i] + h01 * y[i + 1] + h11 * h * dy[i + 1]
    if dmp.dims == 7:
        out[:, 3:] /= np.maximum(np.linalg.norm(out[:, 3:], axis=1, keepdims=True), 1e-12)
    return out


def merge(parts, n_basis_per_part: int = 30, smoothing: float = SMOOTHING) -> DMP:
    """One primitive for consecutive segments, fitted to their concatenation with
    n_basis_per_part bases per segment.

    Each part's times are shifted so that it starts where the previous one ended; its first
    sample, if it repeats the previous part's last pose (within 1e-9), is dropped, otherwise it
    comes one of its own sampling intervals after that end.
    """
    parts = list(parts)
    if not parts:
        raise ValueError("merge needs at least one segment")
    all_t: list[np.ndarray] = []
    all_p: list[np.ndarray] = []
    for number, (times, poses) in enumerate(parts, 1):
        try:
            t, p = _check(times, poses)
        except ValueError as error:
            raise ValueError(f"segment {number}: {error}") from None
        if all_p and p.shape[1] != all_p[0].shape[1]:
            raise ValueError(f"segment {number} has {p.shape[1]} dimensions, segment 1 {all_p[0].shape[1]}")
        t = t - t[0]
        if all_t:
            last = all_p[-1][-1]
            if p.shape[1] == 7 and np.dot(p[0, 3:], last[3:]) < 0:
                p[:, 3:] = -p[:, 3:]
            if np.allclose(p[0], last, rtol=0.0, atol=1e-9):
                t, p = t[1:], p[1:]
                t = t + all_t[-1][-1]
            else:
                t = t + all_t[-1][-1] + (t[1] - t[0])
        all_t.append(t)
        all_p.append(p)
    edges = np.array([0.0] + [t[-1] for t in all_t]) / all_t[-1][-1]
    return _fit(np.concatenate(all_t), np.concatenate(all_p), edges, n_basis_per_part, smoothing)


def reproduction_error(dmp: DMP, times, poses) -> Error:
    """How well the DMP, rolled out at the demonstration's times, reproduces it."""
    t, p = _check(times, poses)
    if p.shape[1] != dmp.dims:
        raise ValueError(f"the poses have {p.shape[1]} dimensions, the DMP {dmp.dims}")
    out = rollout(dmp, t)
    distance = np.linalg.norm(out[:, :3] - p[:, :3], axis=1)
    angle_rms = None
    if dmp.dims == 7:
        dots = np.clip(np.abs(np.einsum("ij,ij->i", out[:, 3:], p[:, 3:])), 0.0, 1.0)
        angle_rms = float(np.sqrt(np.mean((2 * np.arccos(dots)) ** 2)))
    return Error(rms=float(np.sqrt(np.mean(distance ** 2))), max=float(distance.max()),
                 final=float(distance[-1]), angle_rms=angle_rms)


# -- JSON ----------------------------------------------------------------------------------

_FIELDS = ("duration", "start", "goal", "weights", "centers", "widths", "alpha_z", "beta_z", "alpha_x",
           "start_velocity")


def to_json(dmp: DMP) -> dict:
    """The DMP as a JSON-ready dict of numbers and lists."""
    return {"duration": dmp.duration, "start": list(dmp.start), "goal": list(dmp.goal),
            "weights": [list(row) for row in dmp.weights], "centers": list(dmp.centers),
            "widths": list(dmp.widths), "alpha_z": dmp.alpha_z, "beta_z": dmp.beta_z,
            "alpha_x": dmp.alpha_x, "start_velocity": list(dmp.start_velocity)}


def from_json(data: dict) -> DMP:
    """The DMP that to_json wrote."""
    if not isinstance(data, dict):
        raise ValueError(f"a DMP is a JSON object, got {type(data).__name__}")
    missing = [name for name in _FIELDS if name not in data]
    if missing:
        raise ValueError(f"a DMP needs {', '.join(missing)}")
    try:
        return DMP(duration=float(data["duration"]), start=_floats(data["start"]),
                   goal=_floats(data["goal"]), weights=tuple(_floats(row) for row in data["weights"]),
                   centers=_floats(data["centers"]), widths=_floats(data["widths"]),
                   alpha_z=float(data["alpha_z"]), beta_z=float(data["beta_z"]),
                   alpha_x=float(data["alpha_x"]), start_velocity=_floats(data["start_velocity"]))
    except TypeError as error:
        raise ValueError(f"a DMP's fields must be numbers and lists of numbers: {error}") from None
