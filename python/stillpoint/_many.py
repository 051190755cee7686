"""Many designs at once: :func:`generate_many` runs a list of :func:`stillpoint.generate`
requests through any ``concurrent.futures.Executor`` (a local process pool by default,
or a cluster's executor such as Dask's ``Client.get_executor()``), so that the package
needs no scheduling code and no cluster library of its own."""

from __future__ import annotations

import concurrent.futures
import multiprocessing
import os
from typing import Any, Dict, List, Mapping, Optional, Sequence

import numpy as np

from ._generate import generate
from ._request import _check_generate
from ._validate import _executor


def _run(request: Dict[str, Any]) -> np.ndarray:
    """One request in a worker. Module-level, so that a spawned process (or a cluster
    worker) can unpickle it by name."""
    return generate(**request)


def _limit_threads(threads: int) -> None:
    """Runs first in each worker of the default pool: its share of the cores, so that
    the pool's workers do not each start a thread per core (the results do not depend on
    the thread count). A limit the caller set stays."""
    os.environ.setdefault("RAYON_NUM_THREADS", str(threads))


def _checked(requests: Any) -> List[Dict[str, Any]]:
    """The requests as dicts, each refused now (with its index) if :func:`generate`
    would refuse it before running, so that no work starts on a list with a bad entry."""
    if isinstance(requests, (str, bytes, Mapping)) or not hasattr(requests, "__iter__"):
        raise ValueError(
            f"invalid requests = {requests!r}: expected a list of dicts of generate's "
            "keyword arguments"
        )
    out = []
    for i, req in enumerate(requests):
        # n is the one argument generate cannot do without; d may come from a space, a
        # region or a shape, which the check below asks the library about.
        if not isinstance(req, Mapping) or "n" not in req:
            raise ValueError(
                f"invalid requests[{i}] = {req!r}: expected a dict of generate's keyword "
                "arguments with n (and d, unless space, region or shape gives it)"
            )
        req = dict(req)
        try:
            _check_generate(**req)
        except ValueError as e:
            raise ValueError(f"invalid requests[{i}]: {e}") from e
        out.append(req)
    return out


def _collect(
    executor: concurrent.futures.Executor, requests: Sequence[Dict[str, Any]]
) -> List[np.ndarray]:
    """Each request's result in order; on a failure the requests not yet started are
    cancelled, and a refusal names its request."""
    futures = [executor.submit(_run, req) for req in requests]
    results = []
    for i, future in enumerate(futures):
        try:
            results.append(future.result())
        except BaseException as e:
            for later in futures[i + 1 :]:
                later.cancel()
            if isinstance(e, ValueError):
                raise ValueError(f"invalid requests[{i}]: {e}") from e
            raise
    return results


def generate_many(
    requests: Sequence[Mapping[str, Any]],
    executor: Optional[concurrent.futures.Executor] = None,
) -> List[np.ndarray]:
    """The result of :func:`stillpoint.generate` for each request, in request order,
    computed in parallel.

    Each request is a dict of ``generate``'s keyword arguments with at least ``n`` and
    ``d`` (``{"n": 64, "d": 3, "seed": 1}``); each result is the same array, bit for bit,
    as ``generate(**request)`` run alone.

    Parameters
    ----------
    requests : sequence of dict
        The calls to make.
    executor : concurrent.futures.Executor, optional
        Where to run them: anything with ``submit`` returning futures, e.g. a
        ``ProcessPoolExecutor``, Dask's ``Client(...).get_executor()`` or Ray's executor
        (the workers need ``stillpoint`` installed). By default a local process pool
        (spawned processes, one per core, at most one per request, the cores shared
        among them), made for the call and shut down after it; a script using it must
        call it under ``if __name__ == "__main__":``, as for any spawned pool.

    Raises
    ------
    ValueError
        For a request ``generate`` refuses, with ``generate``'s message after
        ``invalid requests[i]:`` (i its index). Every request is checked before any
        runs.
    """
    reqs = _checked(requests)
    if not reqs:
        return []
    if executor is not None:
        _executor(executor)
        return _collect(executor, reqs)
    cores = os.cpu_count() or 1
    workers = min(cores, len(reqs))
    with concurrent.futures.ProcessPoolExecutor(
        max_workers=workers,
        # Spawned, not forked: the parent may already run the library's thread pool,
        # which a fork would copy without its threads.
        mp_context=multiprocessing.get_context("spawn"),
        initializer=_limit_threads,
        initargs=(max(1, cores // workers),),
    ) as pool:
        return _collect(pool, reqs)
