"""Dynamic movement primitives: fitting, rollout, merging, quaternions, JSON, bad input."""

import json
import math
from dataclasses import replace

import numpy as np
import pytest
from hypothesis import given, settings, strategies as st

from schemalog.learn.primitives import DMP, Error, fit, from_json, merge, reproduction_error, rollout, to_json

MM = 1e-3

FAST = settings(max_examples=30, deadline=None)


def minimum_jerk(start, goal, duration, hz=100.0, t0=0.0):
    """A point-to-point minimum-jerk motion sampled at `hz`: (times, positions)."""
    n = int(round(duration * hz)) + 1
    times = t0 + np.linspace(0.0, duration, n)
    s = np.linspace(0.0, 1.0, n)
    shape = 10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5
    start, goal = np.asarray(start, float), np.asarray(goal, float)
    return times, start + np.outer(shape, goal - start)


def slerp(q0, q1, s):
    """Quaternions from q0 to q1 at the fractions s."""
    q0, q1 = np.asarray(q0, float), np.asarray(q1, float)
    angle = math.acos(min(1.0, float(np.dot(q0, q1))))
    if angle < 1e-9:
        return np.tile(q0, (len(s), 1))
    return (np.sin((1 - s) * angle)[:, None] * q0 + np.sin(s * angle)[:, None] * q1) / math.sin(angle)


def unit(v):
    v = np.asarray(v, float)
    return v / np.linalg.norm(v)


def direction():
    return st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 0.1).map(unit)


def point():
    return st.lists(st.floats(-0.6, 0.6), min_size=3, max_size=3).map(np.array)


def path(n_parts, rng):
    """n_parts consecutive minimum-jerk segments turning a corner at each junction."""
    parts, here = [], np.array([0.4, 0.0, 0.3])
    previous = None
    for _ in range(n_parts):
        while True:
            d = unit(rng.normal(size=3))
            if previous is None or abs(np.dot(d, previous)) < 0.7:
                break
        goal = here + rng.uniform(0.1, 0.5) * d
        parts.append(minimum_jerk(here, goal, rng.uniform(0.5, 2.0), t0=rng.uniform(0.0, 100.0)))
        here, previous = goal, d
    return parts


def concatenation(parts):
    """The parts end to end in time, each shared junction sample once."""
    times, poses = [parts[0][0] - parts[0][0][0]], [parts[0][1]]
    for t, p in parts[1:]:
        times.append(t[1:] - t[0] + times[-1][-1])
        poses.append(p[1:])
    return np.concatenate(times), np.concatenate(poses)


# -- one segment -----------------------------------------------------------------------------

def test_a_straight_minimum_jerk_motion_is_reproduced():
    times, poses = minimum_jerk([0.4, -0.1, 0.3], [0.6, 0.1, 0.2], 1.0)
    dmp = fit(times, poses)
    assert dmp.dims == 3 and dmp.n_basis == 30 and dmp.duration == pytest.approx(1.0)
    error = reproduction_error(dmp, times, poses)
    assert error.rms < 1 * MM and error.max < 2 * MM and error.final < 0.5 * MM
    assert error.angle_rms is None
    out = rollout(dmp, samples=3)
    assert out.shape == (3, 3)
    assert np.allclose(out[1], [0.5, 0.0, 0.25], atol=2 * MM)     # halfway at half time
    assert np.allclose(out[2], [0.6, 0.1, 0.2], atol=0.5 * MM)


def test_without_forcing_the_rollout_is_the_critically_damped_spring():
    tau = 2.0
    dmp = DMP(duration=tau, start=(0.0, 1.0, -1.0), goal=(1.0, 1.0, 1.0), weights=((0.0, 0.0, 0.0),),
              centers=(0.5,), widths=(1.0,))
    t = np.linspace(0.0, 3.0, 31)
    omega = 12.5 / tau                         # sqrt(alpha_z * beta_z) / tau, damping alpha_z = 2 * omega * tau
    decay = (1 + omega * t) * np.exp(-omega * t)
    expected = np.array(dmp.goal) + np.outer(decay, np.array(dmp.start) - np.array(dmp.goal))
    assert np.allclose(rollout(dmp, t + 5.0), expected, atol=1e-9)
    assert dmp.start_velocity == (0.0, 0.0, 0.0)                  # at rest unless told otherwise
    pushed = replace(dmp, goal=dmp.start, start_velocity=(0.5, 0.0, -0.5))
    expected = np.array(dmp.start) + np.outer(t * np.exp(-omega * t), [0.5, 0.0, -0.5])
    assert np.allclose(rollout(pushed, t), expected, atol=1e-9)


@FAST
@given(start=point(), towards=direction(), length=st.floats(0.1, 0.5), duration=st.floats(0.5, 2.0),
       t0=st.floats(-100, 100))
def test_rollout_starts_at_the_start_and_ends_at_the_goal(start, towards, length, duration, t0):
    times, poses = minimum_jerk(start, start + length * towards, duration, t0=t0)
    dmp = fit(times, poses)
    out = rollout(dmp, times)
    assert np.array_equal(out[0], np.array(dmp.start))
    assert np.linalg.norm(out[0] - poses[0]) < 0.5 * MM
    assert np.linalg.norm(out[-1] - poses[-1]) < 2 * MM
    error = reproduction_error(dmp, times, poses)
    assert error.rms < 5 * MM and error.final < 2 * MM
    assert error.final == pytest.approx(np.linalg.norm(out[-1] - poses[-1]))


@FAST
@given(start=point(), towards=direction(), length=st.floats(0.1, 0.5), duration=st.floats(0.5, 2.0),
       seed=st.integers(0, 2 ** 32 - 1))
def test_one_millimetre_of_noise_is_smoothed_away(start, towards, length, duration, seed):
    times, clean = minimum_jerk(start, start + length * towards, duration)
    noisy = clean + np.random.default_rng(seed).normal(scale=1 * MM, size=clean.shape)
    error = reproduction_error(fit(times, noisy), times, clean)
    assert error.rms < 5 * MM
    assert error.final < 5 * MM


def test_uneven_time_steps():
    rng = np.random.default_rng(3)
    times = 7.0 + np.cumsum(rng.uniform(0.005, 0.015, 120))
    s = (times - times[0]) / (times[-1] - times[0])
    poses = np.outer(10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5, [0.3, -0.1, 0.2])
    error = reproduction_error(fit(times, poses), times, poses)
    assert error.rms < 1 * MM and error.final < 1 * MM


def test_dimensions_that_do_not_move():
    times, poses = minimum_jerk([0.1, 0.2, 0.3], [0.4, 0.2, 0.3], 1.0)    # y and z stay put
    dmp = fit(times, poses)
    out = rollout(dmp, times)
    assert np.allclose(out[:, 1:], [0.2, 0.3], atol=1e-9)
    assert reproduction_error(dmp, times, poses).rms < 1 * MM
    still = np.tile([0.1, 0.2, 0.3], (50, 1))
    assert np.allclose(rollout(fit(np.linspace(0, 1, 50), still), samples=7), still[:7], atol=1e-12)


@FAST
@given(n=st.integers(2, 5), towards=direction(), length=st.floats(0.001, 0.05),
       gaps=st.lists(st.floats(0.005, 0.03), min_size=4, max_size=4))
def test_a_few_samples_still_fit(n, towards, length, gaps):
    times = np.concatenate([[0.0], np.cumsum(gaps[:n - 1])])
    s = times / times[-1]
    poses = np.outer(10 * s ** 3 - 15 * s ** 4 + 6 * s ** 5, length * towards)
    dmp = fit(times, poses)                   # 30 bases, at most 5 samples
    out = rollout(dmp, times)
    assert np.all(np.isfinite(out))
    assert np.array_equal(out[0], np.array(dmp.start))
    assert np.linalg.norm(out[0] - poses[0]) < 0.05 * length
    assert np.linalg.norm(out[-1] - poses[-1]) < 0.25 * length     # roughly there, not diverging
    assert reproduction_error(dmp, times, poses).max < 0.5 * length


# -- merged segments ---------------------------------------------------------------------------

def test_a_path_with_five_corners_merges_into_one_primitive():
    parts = path(5, np.random.default_rng(11))
    times, poses = concatenation(parts)
    dmp = merge(parts)
    assert dmp.n_basis == 150
    assert dmp.duration == pytest.approx(sum(t[-1] - t[0] for t, _ in parts))
    error = reproduction_error(dmp, times, poses)
    assert error.rms < 1 * MM and error.final < 1 * MM
    # the same with 1 mm of noise, each junction sample shared by the segments it joins
    noise = np.random.default_rng(12).normal(scale=1 * MM, size=poses.shape)
    ends = np.cumsum([0] + [len(t) - 1 for t, _ in parts])
    noisy = [(t, p + noise[a:b + 1]) for (t, p), a, b in zip(parts, ends[:-1], ends[1:])]
    assert merge(noisy).duration == dmp.duration
    assert reproduction_error(merge(noisy), times, poses).rms < 5 * MM


@settings(max_examples=12, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), n_parts=st.integers(2, 5))
def test_merging_scales_the_bases_with_the_segments(seed, n_parts):
    parts = path(n_parts, np.random.default_rng(seed))
    times, poses = concatenation(parts)
    merged = reproduction_error(merge(parts, n_basis_per_part=10), times, poses)
    single = reproduction_error(fit(times, poses, n_basis=10), times, poses)
    assert merged.rms < 1e-2
    assert merged.rms <= single.rms + 1e-5
    assert merged.max <= single.max + 1e-5


def test_merge_makes_time_continuous():
    a = minimum_jerk([0, 0, 0], [0.2, 0, 0], 1.0, t0=50.0)
    b = minimum_jerk([0.2, 0, 0], [0.2, 0.2, 0], 0.5, t0=3.0)     # repeats a's last sample
    assert merge([a, b]).duration == pytest.approx(1.5)
    c = (b[0][1:], b[1][1:])                                        # starts one sample later
    assert merge([a, c]).duration == pytest.approx(1.5)
    assert merge([a]) == fit(*a, n_basis=30)


# -- quaternions -------------------------------------------------------------------------------

def orientation_motion():
    times, positions = minimum_jerk([0.3, 0.0, 0.2], [0.5, 0.1, 0.3], 1.0)
    q0, q1 = unit([0.0, 0.0, 0.0, 1.0]), unit([0.3, 0.2, -0.1, 0.9])
    s = 10 * np.linspace(0, 1, len(times)) ** 3 - 15 * np.linspace(0, 1, len(times)) ** 4 \
        + 6 * np.linspace(0, 1, len(times)) ** 5
    return times, np.hstack([positions, slerp(q0, q1, s)])


@FAST
@given(flips=st.lists(st.booleans(), min_size=101, max_size=101))
def test_quaternion_sign_flips_do_not_change_the_primitive(flips):
    times, poses = orientation_motion()
    flipped = poses.copy()
    flipped[np.array(flips), 3:] *= -1
    original = fit(times, poses)
    assert fit(times, flipped) == original
    assert reproduction_error(original, times, flipped) == reproduction_error(original, times, poses)


def test_orientations_are_reproduced_and_unit():
    times, poses = orientation_motion()
    dmp = fit(times, poses)
    out = rollout(dmp, times)
    assert np.allclose(np.linalg.norm(out[:, 3:], axis=1), 1.0)
    error = reproduction_error(dmp, times, poses)
    assert error.rms < 1 * MM
    assert error.angle_rms is not None and error.angle_rms < math.radians(0.1)
    # a different orientation is measured as such: 2 arccos |<q, q'>|
    turned = poses.copy()
    turned[:, 3:] = [0.0, 0.0, math.sin(0.25), math.cos(0.25)]
    assert reproduction_error(fit(times, turned), times, poses).angle_rms > 0.1


# -- JSON --------------------------------------------------------------------------------------

@settings(max_examples=10, deadline=None)
@given(seed=st.integers(0, 2 ** 32 - 1), orientation=st.booleans())
def test_json_round_trips_exactly(seed, orientation):
    rng = np.random.default_rng(seed)
    times, poses = orientation_motion() if orientation else minimum_jerk(
        rng.uniform(-1, 1, 3), rng.uniform(-1, 1, 3), rng.uniform(0.2, 3))
    poses = poses + rng.normal(scale=1 * MM, size=poses.shape)
    dmp = fit(times, poses, n_basis=int(rng.integers(1, 40)))
    data = json.loads(json.dumps(to_json(dmp)))
    again = from_json(data)
    assert again == dmp
    assert np.array_equal(rollout(again, times), rollout(dmp, times))
    assert to_json(again) == data


def test_bad_json_is_refused():
    data = to_json(fit(*minimum_jerk([0, 0, 0], [0.1, 0, 0], 0.5)))
    for broken in ({k: v for k, v in data.items() if k != "goal"},
                   {**data, "duration": 0.0},
                   {**data, "weights": data["weights"][1:]},
                   {**data, "start": [0.0, 0.0]},
                   {**data, "start_velocity": [0.0]},
                   {**data, "widths": [-1.0] * len(data["widths"])},
                   {**data, "centers": 3},
                   []):
        with pytest.raises(ValueError):
            from_json(broken)


# -- bad input ---------------------------------------------------------------------------------

def test_bad_input_is_refused():
    times, poses = minimum_jerk([0, 0, 0], [0.1, 0, 0], 0.5)
    nan = poses.copy()
    nan[5, 1] = np.nan
    backwards = times.copy()
    backwards[[3, 4]] = backwards[[4, 3]]
    repeated = times.copy()
    repeated[4] = repeated[3]
    cases = {
        "mismatched lengths": (times[:-1], poses),
        "non-increasing times": (backwards, poses),
        "a repeated time": (repeated, poses),
        "NaN": (times, nan),
        "NaN time": (np.where(np.arange(len(times)) == 2, np.nan, times), poses),
        "one sample": (times[:1], poses[:1]),
        "no sample": (times[:0], poses[:0]),
        "four columns": (times, np.hstack([poses, poses[:, :1]])),
        "a zero quaternion": (times, np.hstack([poses, np.zeros((len(times), 4))])),
    }
    for name, (t, p) in cases.items():
        with pytest.raises(ValueError):
            fit(t, p)
        with pytest.raises(ValueError):
            merge([(times, poses), (t, p)])
    with pytest.raises(ValueError, match="at least 2 samples"):
        fit([0.0], [[0.0, 0.0, 0.0]])
    with pytest.raises(ValueError):
        fit(times, poses, n_basis=0)
    with pytest.raises(ValueError):
        merge([])
    dmp = fit(times, poses)
    with pytest.raises(ValueError):
        rollout(dmp, times, samples=10)
    with pytest.raises(ValueError):
        rollout(dmp, times[::-1])
    with pytest.raises(ValueError):
        reproduction_error(dmp, *orientation_motion())


def test_error_fields():
    times, poses = minimum_jerk([0, 0, 0], [0.1, 0, 0], 0.5)
    shifted = poses + [0.0, 0.003, 0.004]                  # 5 mm off everywhere
    dmp = fit(times, poses)
    error = reproduction_error(dmp, times, shifted)
    assert isinstance(error, Error)
    assert error.rms == pytest.approx(5 * MM, abs=0.3 * MM)
    assert error.max >= error.rms and error.final == pytest.approx(5 * MM, abs=0.3 * MM)


# -- cost: banded features and normal equations --------------------------------------------

from schemalog.learn import primitives as P     # noqa: E402  (the internals the cost bounds are about)


def dense_features(x, centers, widths):
    log_psi = -widths[None, :] * (x[:, None] - centers[None, :]) ** 2
    psi = np.exp(log_psi - log_psi.max(axis=1, keepdims=True))
    return psi * (x / psi.sum(axis=1))[:, None]


@FAST
@given(parts=st.lists(st.floats(0.05, 20.0), min_size=1, max_size=6), per_cell=st.integers(1, 300),
       samples=st.integers(2, 400))
def test_banded_features_are_the_dense_ones_and_their_width_does_not_grow_with_the_bases(parts, per_cell, samples):
    edges = np.concatenate([[0.0], np.cumsum(parts)]) / sum(parts)     # unequal merged parts
    centers, widths = P._basis(P._cells(edges, per_cell), P.ALPHA_X)
    x = np.exp(-P.ALPHA_X * np.linspace(0.0, 1.0, samples))
    values, first = P._features(x, centers, widths)
    dense = np.zeros((samples, len(centers)))
    for a in range(values.shape[1]):
        dense[np.arange(samples), first + a] = values[:, a]
    assert np.allclose(dense, dense_features(x, centers, widths), rtol=0, atol=1e-15)
    if len(parts) == 1:
        # bounded whatever the number of bases: every basis up to about 20 of them (14 bases
        # at 2 samples take all 14), then fewer as they narrow: 11 at 60-100, 10 at 300
        assert values.shape[1] <= min(len(centers), 22)
        if len(centers) >= 60:
            assert values.shape[1] <= 11


@FAST
@given(n=st.integers(1, 60), width=st.integers(1, 6), seed=st.integers(0, 2 ** 16))
def test_the_banded_solver_solves(n, width, seed):
    rng = np.random.default_rng(seed)
    m = rng.normal(size=(n, n))
    a = m @ m.T + n * np.eye(n)
    a[np.abs(np.subtract.outer(np.arange(n), np.arange(n))) >= width] = 0.0
    a += n * np.eye(n)                          # still positive definite after the cut
    upper = np.zeros((width, n))
    for o in range(min(width, n)):              # a band wider than the matrix: rows of zeros
        upper[o, :n - o] = np.diagonal(a, o)
    rhs = rng.normal(size=(n, 3))
    assert np.allclose(P._solve_banded(upper, rhs), np.linalg.solve(a, rhs), atol=1e-9)


def test_a_thousand_bases_on_a_few_samples_allocate_per_sample_and_basis_not_per_basis_squared():
    # The bug: 1000 bases per part on a 5-part merged action tried to allocate 3.73 GiB, the rollout
    # grid (20 steps per basis) times every basis.
    parts = [minimum_jerk([0.1 * k, 0, 0], [0.1 * (k + 1), 0.05, 0], 0.4, hz=20.0, t0=0.4 * k) for k in range(5)]
    dmp = merge(parts, n_basis_per_part=1000)
    assert dmp.n_basis == 5000
    steps = 20 * dmp.n_basis
    values, first = P._features(np.exp(-P.ALPHA_X * np.linspace(0, 1, steps + 1)), np.array(dmp.centers),
                                np.array(dmp.widths))
    assert values.shape[1] <= 13                # banded: steps x 13, not steps x 5000 (3.73 GiB)
    out = rollout(dmp, concatenation(parts)[0])
    assert np.all(np.isfinite(out))


def test_many_samples_per_basis_are_binned_so_the_fit_sees_at_most_32_per_basis():
    times, poses = minimum_jerk([0.1, 0.2, 0.3], [0.4, 0.0, 0.1], 2.0, hz=50_000.0)
    t, p, counts = P._binned(times, poses, math.ceil(len(times) / 30 / P._PER_BASIS))
    assert len(t) <= 30 * P._PER_BASIS + 2 and counts.sum() == len(times)
    assert t[0] == times[0] and t[-1] == times[-1] and np.all(np.diff(t) > 0)
    noisy = poses + np.random.default_rng(5).normal(scale=1 * MM, size=poses.shape)
    error = reproduction_error(fit(times, noisy), times, poses)
    assert error.rms < 0.5 * MM and error.final < 1 * MM      # 100k noisy samples average the noise away
