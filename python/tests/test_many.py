"""stillpoint.generate_many: many designs through any concurrent.futures executor, with
the same bytes as one generate call after another."""

import concurrent.futures
import logging

import numpy as np
import pytest
from dask.distributed import Client, LocalCluster

import stillpoint as sp

REQUESTS = [
    {"n": 64, "d": 3},
    {"n": 40, "d": 2, "seed": 5, "randomize": "cells"},
    {"n": 32, "d": 4, "method": "paper", "steps": 50},
    {"n": 48, "d": 2, "method": "sobol", "seed": 1},
]


@pytest.fixture(scope="module")
def one_by_one():
    return [sp.generate(**req) for req in REQUESTS]


def assert_same(results, expected):
    assert isinstance(results, list) and len(results) == len(expected)
    for got, want in zip(results, expected):
        assert got.dtype == want.dtype and got.shape == want.shape
        assert got.tobytes() == want.tobytes()


def test_the_default_pool_gives_the_sequential_results(one_by_one):
    assert_same(sp.generate_many(REQUESTS), one_by_one)


def test_any_executor_gives_the_sequential_results_in_order(one_by_one):
    with concurrent.futures.ThreadPoolExecutor(max_workers=3) as pool:
        assert_same(sp.generate_many(REQUESTS, executor=pool), one_by_one)
    # Order is the requests', not the order of completion.
    with concurrent.futures.ThreadPoolExecutor(max_workers=3) as pool:
        assert_same(sp.generate_many(REQUESTS[::-1], pool), one_by_one[::-1])


def test_dask_distributed_executor_gives_the_sequential_results(one_by_one):
    with LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        dashboard_address=":0",
        silence_logs=logging.ERROR,
    ) as cluster, Client(cluster) as client:
        with client.get_executor() as executor:
            assert_same(sp.generate_many(REQUESTS, executor=executor), one_by_one)
            bad = REQUESTS[:1] + [{"n": 8, "d": 2, "extend": np.full((4, 3), 0.5)}]
            with pytest.raises(ValueError, match=r"^invalid requests\[1\]: invalid d = 2"):
                sp.generate_many(bad, executor=executor)


@pytest.mark.parametrize(
    "bad, message",
    [
        ({"n": 16, "d": 2, "steps": 0}, r"^invalid requests\[2\]: invalid steps = 0: "),
        ({"n": 0, "d": 2}, r"^invalid requests\[2\]: invalid n = 0"),
        ({"n": 16, "d": 2, "colour": 1}, r"^invalid requests\[2\]: .*colour"),
        ({"n": 16}, r"^invalid requests\[2\]: invalid d = none: expected the dimension"),
        ({"d": 2}, r"^invalid requests\[2\] = \{'d': 2\}: expected a dict .* with n"),
        ([16, 2], r"^invalid requests\[2\] = \[16, 2\]: expected a dict"),
    ],
)
def test_a_bad_request_is_named_by_its_index_before_any_work(bad, message):
    class Refuses(concurrent.futures.Executor):
        def submit(self, fn, *args, **kwargs):
            raise AssertionError("no request may start when one is bad")

    requests = [{"n": 16, "d": 2}, {"n": 16, "d": 3}, bad]
    with pytest.raises(ValueError, match=message) as caught:
        sp.generate_many(requests, executor=Refuses())
    if isinstance(bad, dict) and "n" in bad and "d" in bad:
        # generate's own message follows the index, unchanged.
        with pytest.raises(ValueError) as direct:
            sp.generate(**bad)
        assert str(caught.value) == f"invalid requests[2]: {direct.value}"


def test_a_refusal_from_a_worker_names_its_request_and_cancels_the_rest():
    class FailsSecond(concurrent.futures.Executor):
        """Runs the first request, fails the second as a worker would, holds the rest."""

        def __init__(self):
            self.futures = []

        def submit(self, fn, *args, **kwargs):
            f = concurrent.futures.Future()
            if len(self.futures) == 0:
                f.set_result(fn(*args, **kwargs))
            elif len(self.futures) == 1:
                f.set_exception(ValueError("invalid n = 3: expected more memory"))
            self.futures.append(f)
            return f

    pool = FailsSecond()
    with pytest.raises(ValueError) as caught:
        sp.generate_many([{"n": 4, "d": 2}] * 4, executor=pool)
    assert str(caught.value) == "invalid requests[1]: invalid n = 3: expected more memory"
    assert [f.cancelled() for f in pool.futures] == [False, False, True, True]


def test_the_arguments_themselves_are_checked():
    assert sp.generate_many([]) == []
    with pytest.raises(ValueError, match=r"^invalid requests = \{'n': 4"):
        sp.generate_many({"n": 4, "d": 2})
    with pytest.raises(ValueError, match=r"^invalid executor = 3: expected a "):
        sp.generate_many([{"n": 4, "d": 2}], executor=3)
