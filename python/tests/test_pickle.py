"""Everything the package returns, and its Engine, survives pickle and deepcopy: an
unpickled Engine goes on drawing exactly what the original would have drawn, in this
process or in another one."""

import concurrent.futures
import copy
import multiprocessing
import pickle

import numpy as np
import pytest

import stillpoint as sp


def roundtrips(value):
    return [pickle.loads(pickle.dumps(value, protocol=p)) for p in (2, pickle.HIGHEST_PROTOCOL)] + [
        copy.deepcopy(value)
    ]


def test_results_pickle_to_equal_values():
    x = sp.generate(24, 3)
    values = [
        x,
        sp.baseline("sobol", 16, 2, seed=1),
        sp.metrics(x),
        sp.integrate(x),
        sp.integrate(x, lambda p: p[:, 0]),
        sp.discrepancy(x, "modified"),
        sp.baselines(),
    ]
    for value in values:
        for back in roundtrips(value):
            if isinstance(value, np.ndarray):
                assert back.dtype == value.dtype and back.tobytes() == value.tobytes()
            else:
                assert back == value


def test_a_refusal_pickles_with_its_message():
    with pytest.raises(ValueError) as caught:
        sp.generate(10, 2, steps=0)
    back = pickle.loads(pickle.dumps(caught.value))
    assert type(back) is ValueError and str(back) == str(caught.value)


ENGINES = [
    dict(d=3, seed=4),
    dict(d=2, seed=np.random.default_rng(7), steps=40, energy="e-inf", shifts=0),
    dict(d=2, rng=np.random.Generator(np.random.MT19937(3))),
    dict(d=2, seed=5, optimization="random-cd"),
    dict(d=3, seed=6, randomize="cells"),
]


@pytest.mark.parametrize("args", ENGINES)
def test_an_engine_copy_draws_what_the_original_draws(args):
    e = sp.Engine(**dict(args))
    e.random(16)
    e.fast_forward(8)
    for back in roundtrips(e):
        assert back == e and back is not e
        assert back.num_generated == e.num_generated == 24
        assert back.d == e.d and repr(back) == repr(e)
    copies = roundtrips(e)
    expected = [e.random(16), e.random(32)]
    for c in copies:
        assert [c.random(16).tobytes(), c.random(32).tobytes()] == [a.tobytes() for a in expected]
        assert c == e
    # reset goes back to the same first draw in the copies too.
    first = e.reset().random(16)
    for c in copies:
        assert c.reset().random(16).tobytes() == first.tobytes()


def test_engines_differ_when_their_draws_would():
    a, b = sp.Engine(2, seed=1), sp.Engine(2, seed=1)
    assert a == b
    a.random(8)
    assert a != b
    b.random(8)
    assert a == b
    assert sp.Engine(2, seed=1) != sp.Engine(2, seed=2)
    assert sp.Engine(2, seed=1) != sp.Engine(3, seed=1)
    assert sp.Engine(2, seed=1) != sp.Engine(2, seed=1, steps=30)
    assert sp.Engine(2, seed=1) != sp.Engine(2, seed=1, randomize="cells")
    with pytest.raises(TypeError):
        hash(a)


def draw_twice(engine):
    """In a worker: the engine's next two draws."""
    return engine.random(32), engine.random(32), engine.num_generated


def test_an_engine_sent_to_a_worker_process_draws_the_same_points():
    e = sp.Engine(3, seed=9, steps=60)
    e.random(32)
    sent = pickle.dumps(e)
    with concurrent.futures.ProcessPoolExecutor(
        max_workers=1, mp_context=multiprocessing.get_context("spawn")
    ) as pool:
        a, b, count = pool.submit(draw_twice, pickle.loads(sent)).result(timeout=120)
    assert a.tobytes() == e.random(32).tobytes()
    assert b.tobytes() == e.random(32).tobytes()
    assert count == e.num_generated == 96
