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
term linear between grid points; the recurrence as a vectorised prefix scan), then reads the
times asked for off cubic Hermite splines.

Costs are linear in samples x bases and far below it: a sample touches only the K bases whose
Gaussians reach it (about 11), so the features are banded (samples x K), the normal equations
too (built in samples x K^2, solved by block elimination in bases x K^2), and the rollout's grid
(20 steps per basis) costs steps x K. Over more than 32 samples per basis, the fit averages the
inner samples in bins first (the first and last kept as they are): a basis cannot show detail
finer than itself, and the smoothing window (a quarter of a basis) would otherwise grow with
the samples, making the cost quadratic in a long recording's length.
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
_SUPPORT = 50.0                    # a basis counts where its exponent is above -50 (e^-50 = 2e-22)
_PER_BASIS = 32                    # fit points per basis: more samples are averaged into bins


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


def _smooth(t: np.ndarray, y: np.ndarray, sigma: float, degree: int = 2,
            counts: np.ndarray | None = None) -> np.ndarray:
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
        if counts is not None:
            weight = weight * counts[i + k][:, None, None]
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


def _features(x: np.ndarray, centers: np.ndarray, widths: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """psi_i(x) x / sum_j psi_j(x) for every phase in x, banded: values (len(x), K) and the first
    basis of each row (len(x),), row r holding bases first[r] .. first[r] + K - 1.

    A basis is 0 (below e^-50 of the largest) outside |x - c_i| < sqrt(50 / h_i); every phase is
    near a centre, so the K bases around it are all there is: the cost is len(x) * K, not
    len(x) * n_basis (K is about 11 for evenly spread centres, whatever their number).
    """
    n_basis = len(centers)
    reach = np.sqrt(_SUPPORT / widths)
    # centres decrease along the bases; the first basis that may reach x: the first whose support
    # starts below x (a running minimum keeps the search monotone), the last: the last whose
    # support ends above it (a running maximum from the end)
    low = np.minimum.accumulate(centers - reach)
    high = np.maximum.accumulate((centers + reach)[::-1])[::-1]
    lo = np.searchsorted(-low, -x, side="left")
    hi = np.searchsorted(-high, -x, side="right") - 1
    nearest = np.clip(np.searchsorted(-centers, -x), 0, n_basis - 1)
    nearest = np.where((nearest > 0) & (np.abs(centers[nearest - 1] - x) < np.abs(centers[nearest] - x)),
                       nearest - 1, nearest)
    lo, hi = np.minimum(np.clip(lo, 0, n_basis - 1), nearest), np.maximum(np.clip(hi, 0, n_basis - 1), nearest)
    k = int((hi - lo).max(initial=0)) + 1
    first = np.clip(lo, 0, n_basis - k)
    index = first[:, None] + np.arange(k)[None, :]
    log_psi = -widths[index] * (x[:, None] - centers[index]) ** 2
    log_psi -= log_psi.max(axis=1, keepdims=True)
    psi = np.exp(log_psi)
    return psi * (x / psi.sum(axis=1))[:, None], first


def _banded_product(values: np.ndarray, first: np.ndarray, weights: np.ndarray) -> np.ndarray:
    """The dense features times weights (n_basis, dims), from the banded features."""
    out = np.zeros((len(values), weights.shape[1]))
    for a in range(values.shape[1]):
        out += values[:, a:a + 1] * weights[first + a]
    return out


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
    n_basis = int(per_cell) * (len(edges) - 1)
    per_basis = len(t) / n_basis
    sigma = max(smoothing, per_basis / 4) if smoothing > 0 else 0.0
    t, p, counts = _binned(t, p, math.ceil(per_basis / _PER_BASIS))
    bin_size = 1 if counts is None else float(np.mean(counts[1:-1]))
    y = _smooth(t, p, sigma / bin_size, counts=counts)
    tau = float(t[-1] - t[0])
    order = 2 if len(t) > 2 else 1
    yd = np.gradient(y, t, axis=0, edge_order=order)
    ydd = np.gradient(yd, t, axis=0, edge_order=order)
    start, goal = y[0], y[-1]
    alpha_z, beta_z, alpha_x = 25.0, 6.25, ALPHA_X
    target = (tau ** 2 * ydd - alpha_z * (beta_z * (goal - y) - tau * yd)) / _scale(start, goal)
    centers, widths = _basis(_cells(edges, int(per_cell)), alpha_x)
    values, first = _features(np.exp(-alpha_x * (t - t[0]) / tau), centers, widths)
    values = values / centers[first[:, None] + np.arange(values.shape[1])]
    weights = _regress(values, first, n_basis, target, counts) / centers[:, None]
    return DMP(duration=tau, start=_floats(start), goal=_floats(goal),
               weights=tuple(_floats(row) for row in weights),
               centers=_floats(centers), widths=_floats(widths),
               alpha_z=alpha_z, beta_z=beta_z, alpha_x=alpha_x, start_velocity=_floats(yd[0]))


def _binned(t: np.ndarray, p: np.ndarray, size: int) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """The trajectory with its inner samples averaged in bins of `size` (time and pose), the
    first and last kept as they are, and how many samples each point stands for (None: size 1)."""
    if size <= 1 or len(t) < 3:
        return t, p, None
    inner = len(t) - 2
    edges = np.arange(0, inner, size)
    counts = np.diff(np.append(edges, inner)).astype(float)
    sums_t = np.add.reduceat(t[1:-1], edges)
    sums_p = np.add.reduceat(p[1:-1], edges, axis=0)
    return (np.concatenate([t[:1], sums_t / counts, t[-1:]]),
            np.concatenate([p[:1], sums_p / counts[:, None], p[-1:]]),
            np.concatenate([[1.0], counts, [1.0]]))


def _regress(values: np.ndarray, first: np.ndarray, n_basis: int, target: np.ndarray,
             counts: np.ndarray | None = None) -> np.ndarray:
    """Least-squares weights, regularised towards a forcing term smooth across the bases.

    Columns are scaled by their centre, so the unknowns are forcing values near each basis;
    the penalty on their second differences fills the bases no sample reaches by
    interpolation instead of pulling them to zero. The normal equations are banded (a sample
    touches K neighbouring bases, the penalty 5), so they are built and solved in
    O(samples K^2 + n_basis K^2), never as an n_basis x n_basis matrix.
    """
    k = values.shape[1]
    weighted = values if counts is None else values * counts[:, None]
    order = min(2, n_basis - 1)
    bands = max(k, order + 1)
    upper = np.zeros((bands, n_basis))           # upper[o, j] = A[j, j + o]
    for a in range(k):
        for o in range(k - a):
            upper[o] += np.bincount(first + a, weights=weighted[:, a] * values[:, a + o], minlength=n_basis)
    rhs = np.zeros((n_basis, target.shape[1]))
    for a in range(k):
        for d in range(target.shape[1]):
            rhs[:, d] += np.bincount(first + a, weights=weighted[:, a] * target[:, d], minlength=n_basis)
    level = max(float(np.mean(upper[0])), 1e-300)
    # the penalty D^T D + 1e-3 I, D the `order`-th differences: banded too
    coefficients = np.diff(np.eye(order + 1), n=order, axis=0)[0] if order else np.ones(1)
    penalty = np.zeros((bands, n_basis))
    rows = n_basis - order
    for a in range(order + 1):
        for o in range(order + 1 - a):
            penalty[o, a:a + rows] += coefficients[a] * coefficients[a + o]
    penalty[0] += 1e-3
    return _solve_banded(upper + RIDGE * level * penalty, rhs)


def _solve_banded(upper: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """x with A x = rhs for a symmetric positive definite A given by its upper bands
    (upper[o, j] = A[j, j + o]): A is block tridiagonal in blocks of the band's width, solved by
    block elimination (n / width solves of width x width systems)."""
    width, n = upper.shape
    blocks = -(-n // width)

    def entry(i: np.ndarray, j: np.ndarray) -> np.ndarray:
        low, offset = np.minimum(i, j), np.abs(i - j)
        inside = (offset < width) & (np.maximum(i, j) < n)
        value = np.where(inside, upper[np.minimum(offset, width - 1), np.minimum(low, n - 1)], 0.0)
        return np.where((i == j) & (i >= n), 1.0, value)          # the padding: identity

    base = (np.arange(blocks) * width)[:, None, None]
    i = base + np.arange(width)[None, :, None]
    j = base + np.arange(width)[None, None, :]
    diagonal, above = entry(i, j), entry(i, j + width)
    b = np.zeros((blocks * width, rhs.shape[1]))
    b[:n] = rhs
    b = b.reshape(blocks, width, -1)
    for k in range(1, blocks):
        solved = np.linalg.solve(diagonal[k - 1], np.concatenate([above[k - 1], b[k - 1]], axis=1))
        diagonal[k] -= above[k - 1].T @ solved[:, :width]
        b[k] -= above[k - 1].T @ solved[:, width:]
    x = np.empty_like(b)
    x[-1] = np.linalg.solve(diagonal[-1], b[-1])
    for k in range(blocks - 2, -1, -1):
        x[k] = np.linalg.solve(diagonal[k], b[k] - above[k] @ x[k + 1])
    return x.reshape(blocks * width, -1)[:n]


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
    force = _banded_product(*_features(np.exp(-dmp.alpha_x * grid / tau), centers, widths), weights)
    force *= _scale(start, goal)
    # state v = (y - g, z): dv/dt = A v + B u, u = f * scale, linear between grid points
    a = np.array([[0.0, 1.0], [-dmp.alpha_z * dmp.beta_z, -dmp.alpha_z]]) / tau
    b = np.array([0.0, 1.0 / tau])
    big = np.zeros((4, 4))
    big[:2, :2], big[:2, 2], big[2, 3] = a * h, b * h, 1.0
    e = _expm(big)
    ad, b0, b1 = e[:2, :2], e[:2, 2] - e[:2, 3], e[:2, 3]
    # v[k + 1] = ad v[k] + u[k], so v[k] = sum over j <= k of ad^(k - j) s[j] with s = (v[0], u[0], ...):
    # a prefix scan in log2(steps) vectorised passes (pass p adds the terms 2^p further back)
    states = np.empty((steps + 1, 2, dmp.dims))
    states[0] = np.stack([start - goal, tau * np.array(dmp.start_velocity)])
    states[1:] = b0[None, :, None] * force[:-1, None, :] + b1[None, :, None] * force[1:, None, :]
    power, shift = ad, 1
    while shift <= steps:
        earlier = states[:-shift].copy()
        states[shift:, 0] += power[0, 0] * earlier[:, 0] + power[0, 1] * earlier[:, 1]
        states[shift:, 1] += power[1, 0] * earlier[:, 0] + power[1, 1] * earlier[:, 1]
        power, shift = power @ power, 2 * shift
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
