"""Shards are verified: solve_sharded refuses a shard tracked for another
system (or seed), naming it, before any merge; the C merge itself checks
every certified record against Q (tests/test_homotopy_shard.c)."""
import concurrent.futures

import numpy as np
import pytest

import libkin
from libkin.errors import StateError
from libkin.homotopy import shards


class _Swapping(concurrent.futures.Executor):
    """Runs tasks here, but shard `bad` with another system or seed: a shard
    from another job, as a stale cache or a mixed-up store would give."""

    def __init__(self, bad, **change):
        self.bad, self.change, self.n = bad, change, 0

    def submit(self, fn, item):
        k, self.n = self.n, self.n + 1
        f = concurrent.futures.Future()
        f.set_result(fn(dict(item, **self.change) if k == self.bad else item))
        return f


@pytest.fixture(scope="module")
def systems():
    Q = libkin.Assembly.sail(4, 1).second_order()
    rng = np.random.default_rng(3)
    A = rng.standard_normal(Q.shape)
    return Q, (A + A.transpose(0, 2, 1)) / 2


def test_a_shard_of_another_system_is_refused_and_named(systems):
    Q, other = systems
    with pytest.raises(StateError) as exc:
        shards.solve_sharded(Q, _Swapping(1, Q=other.tolist()), shards=3)
    assert exc.value.shard == 1


def test_a_shard_of_another_seed_is_refused(systems):
    Q, _ = systems
    with pytest.raises(StateError) as exc:
        shards.solve_sharded(Q, _Swapping(2, seed=7), shards=3)
    assert exc.value.shard == 2


def test_honest_shards_give_the_one_call_result(systems):
    Q, _ = systems
    betas, acc = shards.solve_sharded(Q, _Swapping(-1), shards=3)
    ref, ref_acc = libkin.solve_quadrics(Q, threads=1)
    assert np.array_equal(betas, ref) and all(acc[k] == ref_acc[k] for k in acc)


def test_fingerprint_tells_systems_and_seeds_apart(systems):
    Q, other = systems
    f = shards.fingerprint(Q, 1)
    assert f == shards.fingerprint(np.array(Q.tolist()), 1)
    assert f != shards.fingerprint(other, 1) and f != shards.fingerprint(Q, 2)
    assert f != shards.fingerprint(np.nextafter(Q, 1.0), 1)
