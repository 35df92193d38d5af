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

Reaching the scheduler is bounded (E118 within CONNECT_TIMEOUT_S, docs/scale.md): Dask's
Client waits without limit for the handshake of a peer that accepts the connection and never
answers (distributed 2026.11, comm.core.connect reads the handshake without a timeout), and a
Client whose start failed spends 20 s closing itself when it is collected, with an "Exception
ignored in Client.__del__" traceback. So the address is checked first (tcp:// or tls://, the
TLS settings there), then one handshake is made with the scheduler under our own deadline, and
only a scheduler that answered gets a Client.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

CONNECT_TIMEOUT_S = 10
SCHEMES = ("tcp", "tls")


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
    security = _security(address)
    _handshake(address, security)
    try:
        client = Client(address, timeout=CONNECT_TIMEOUT_S, set_as_default=False, security=security)
    except (OSError, TimeoutError, ValueError, TypeError) as e:
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
        except MemoryError as e:
            raise ClusterError(f"the Dask cluster at {address} sent a message too large to hold ({e})") from e
        except Exception as e:  # noqa: BLE001 - a worker's failure, re-raised by gather
            raise ClusterError(f"a worker of {address} failed: {type(e).__name__}: {e}") from e
    finally:
        client.close(timeout=CONNECT_TIMEOUT_S)
    return parts


def _security(address: str):
    """Dask's connection settings for `address`: tcp:// as it is; tls:// with the certificates
    of the Dask configuration (distributed.comm.tls: ca-file, client cert and key; docs/scale.md),
    refused when there are none (Dask would fail later, with a TypeError and no hint)."""
    from distributed.comm.addressing import parse_address
    from distributed.security import Security

    try:
        scheme, location = parse_address(address)
    except (ValueError, TypeError) as e:
        raise ClusterError(f"{address!r} is no scheduler address (tcp://HOST:PORT or tls://HOST:PORT)") from e
    if scheme not in SCHEMES or not location:
        raise ClusterError(f"{address!r}: --cluster takes tcp://HOST:PORT or tls://HOST:PORT")
    security = Security()
    if scheme == "tls":
        try:
            context = security.get_connection_args("client")["ssl_context"]
        except (OSError, ValueError) as e:  # a certificate file missing or unreadable
            raise ClusterError(f"{address}: the TLS settings of the Dask configuration cannot be used: {e}") from e
        if context is None:
            raise ClusterError(f"{address}: tls:// needs the TLS settings of the Dask configuration "
                               "(distributed.comm.tls: ca-file, client cert and key; docs/scale.md); none are set")
    return security


def _handshake(address: str, security) -> None:
    """One Dask handshake with the scheduler, within CONNECT_TIMEOUT_S whatever the peer does
    (refuses, accepts and stays silent, answers something else): ClusterError otherwise."""
    import asyncio

    from distributed.comm import connect

    async def shake() -> None:
        comm = await connect(address, timeout=CONNECT_TIMEOUT_S, **security.get_connection_args("client"))
        await comm.close()

    try:
        asyncio.run(asyncio.wait_for(shake(), CONNECT_TIMEOUT_S))
    except TimeoutError as e:
        raise ClusterError(f"the Dask scheduler at {address} did not answer within {CONNECT_TIMEOUT_S} s") from e
    except (OSError, ValueError, TypeError, EOFError) as e:
        raise ClusterError(f"cannot reach the Dask scheduler at {address}: {e}") from e
    except MemoryError as e:  # its first message announced a size no memory holds (not "out of memory")
        raise ClusterError(f"{address} did not answer as a Dask scheduler: it announced a message too large "
                           f"to hold ({e})") from e
    except Exception as e:  # noqa: BLE001 - whatever the peer sent that is no Dask handshake
        raise ClusterError(f"{address} did not answer as a Dask scheduler: {type(e).__name__}: {e}") from e
