"""Campaigns on a Dask distributed cluster: `mlc test --cluster tcp://HOST:PORT` and
`mlc sim PROGRAM --stimulus 'tests/*.stim' --cluster tcp://HOST:PORT` (docs/scale.md).

The client (the mlc process) reads every stimulus file itself, so the workers need no shared
folder: they receive the linked image, the target and the options once (scattered to every
worker), then chunks of (path, loaded stimulus), contiguous in the order of the run. Each chunk
runs exactly as the local run would (a batch chunk as lanes where it can), and the results are
gathered back in that order: the JSON, JUnit and exit status are those of the local run.
Workers run the same mlctool (a worker with another version could give other results: install
the same version everywhere).

`distributed` is optional (`pip install 'mlctool[cluster]'`), imported only here.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

CONNECT_TIMEOUT_S = 10


class ClusterError(Exception):
    """The cluster could not be used (E118): no `distributed`, no scheduler, a worker failed."""


def cluster_diagnostic(e: ClusterError):
    from mlctool.diagnostics import Span, diag

    return diag("<--cluster>", Span.at(1), "E118", str(e))


def chunks(items: Sequence, n: int) -> list[list]:
    """`items` in at most n contiguous slices of near-equal size, in order."""
    n = max(1, min(n, len(items)))
    size, extra = divmod(len(items), n)
    out, at = [], 0
    for k in range(n):
        step = size + (k < extra)
        out.append(list(items[at:at + step]))
        at += step
    return out


def map_chunks(address: str, fn: Callable, shared, items: Sequence, per_thread: int = 1) -> list:
    """fn(shared, chunk) for contiguous chunks of `items` on the cluster at `address` (about
    per_thread chunks per worker thread); fn's results, one per chunk, in order."""
    try:
        from distributed import Client
    except ImportError as e:
        raise ClusterError("--cluster needs Dask distributed: pip install 'mlctool[cluster]'") from e
    try:
        client = Client(address, timeout=CONNECT_TIMEOUT_S, set_as_default=False)
    except (OSError, TimeoutError, ValueError) as e:
        raise ClusterError(f"cannot reach the Dask scheduler at {address}: {e}") from e
    try:
        threads = sum(client.nthreads().values())
        if threads == 0:
            raise ClusterError(f"the Dask scheduler at {address} has no workers")
        shared_future = client.scatter(shared, broadcast=True, hash=False)
        futures = [client.submit(fn, shared_future, chunk, pure=False)
                   for chunk in chunks(items, threads * per_thread)]
        try:
            parts = client.gather(futures)
        except (OSError, TimeoutError) as e:
            raise ClusterError(f"the Dask cluster at {address} failed: {e}") from e
        except Exception as e:  # noqa: BLE001 - a worker's failure, re-raised by gather
            raise ClusterError(f"a worker of {address} failed: {type(e).__name__}: {e}") from e
    finally:
        client.close()
    return parts
