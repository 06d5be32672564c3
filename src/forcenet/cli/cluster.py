"""Options of the routes over independent primes: ``--scheduler`` (a Dask cluster), its TLS, ``--checkpoint``.

``forcenet table --method pfaffian`` and the floor's route of ``forcenet dist``
hand their per-prime tasks to an executor (:func:`forcenet.core.execution.run_tasks`);
this module turns the options into that executor (a Dask client) and a
checkpoint store, refusing them for a route that does not run over primes.

Reaching a scheduler is bounded at every step and each failure is one line
(:class:`~forcenet.cli.common.UsageError`, exit code 2): the address or the
scheduler file is read and checked first (a missing file is called missing,
a garbage or foreign file is named, only ``tcp://`` and ``tls://`` are
taken); then a plain TCP connection (refused at once, or no answer within
:data:`CONNECT_SECONDS`), the TLS handshake with the certificates given
(``--tls-ca-file``, ``--tls-cert``, ``--tls-key``, else Dask's own
configuration ``distributed.comm.tls.*``), and Dask's ``identity`` request
(a server that is not a Dask scheduler does not answer it); only then the
client, the wait for a first worker, announced, and one tiny task that
imports forcenet on a worker (a cluster whose workers cannot is refused in
seconds, by name).  A Dask scheduler runs
whatever its clients send (pickled functions): a cluster is for one user's
machines, bound to loopback or a private interface, with TLS.
"""

from __future__ import annotations

import json
import logging
import os
import socket
import sys
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from forcenet.core.checkpoints import default_directory
from forcenet.core.execution import check_cluster

from .common import FORCE_SECONDS, UsageError
from .output import check_output_dir

if TYPE_CHECKING:
    import argparse

    from forcenet.core.checkpoints import CheckpointStore

__all__ = ["DISTRIBUTED_MISSING", "CONNECT_SECONDS", "WORKER_SECONDS", "scheduler_address", "connect_scheduler",
           "add_engine_options", "engine_options", "report_checkpoints"]

DISTRIBUTED_MISSING = "--scheduler needs Dask's distributed scheduler: pip install 'forcenet[distributed]'"
CONNECT_SECONDS = 5.0  # each step of reaching the scheduler: TCP, TLS, Dask's identity, the client
WORKER_SECONDS = 10.0  # waiting for a cluster's first worker
_SCHEDULER_FILE_BYTES = 2**16  # `dask scheduler --scheduler-file` writes a few hundred bytes
_SCHEMES = ("tcp", "tls")
_TLS_OPTIONS = ("tls_ca_file", "tls_cert", "tls_key")


def _refuse(address: str, why: str) -> UsageError:
    shown = address if len(address) <= 80 else f"{address[:60]}... ({len(address)} characters)"
    return UsageError(f"--scheduler={shown}: {why}")


def _host_name_problem(host: str) -> str | None:
    """Why ``host`` cannot be a DNS name (RFC 1035: labels of 1..63 octets, at most 253 in all), or None."""
    try:
        octets = host.encode("idna")
    except UnicodeError:
        return "a label of the host name is empty or longer than 63 characters"
    if len(octets) > 253:
        return f"the host name has {len(octets)} characters, more than DNS allows (253)"
    return None


def scheduler_address(text: str) -> tuple[str, str, str, int]:
    """``(address, scheme, host, port)`` of ``--scheduler``: a ``tcp://``/``tls://`` address or a scheduler file.

    Raises
    ------
    UsageError
        One line: a missing, unreadable or foreign scheduler file, another
        protocol, a malformed host or port.

    Examples
    --------
    >>> scheduler_address("tls://127.0.0.1:8786")
    ('tls://127.0.0.1:8786', 'tls', '127.0.0.1', 8786)
    >>> scheduler_address("ucx://127.0.0.1:8786")
    Traceback (most recent call last):
    ...
    forcenet.cli.common.UsageError: --scheduler=ucx://127.0.0.1:8786: the protocol ucx:// is not supported: give tcp://HOST:PORT or tls://HOST:PORT of a running `dask scheduler`, or its scheduler file
    """
    address = text if "://" in text else _read_scheduler_file(text)
    scheme, _, rest = address.partition("://")
    where = "" if address == text else f" (from the scheduler file {text})"
    if scheme not in _SCHEMES:
        raise _refuse(text, f"the protocol {scheme}:// is not supported{where}: give tcp://HOST:PORT or "
                            "tls://HOST:PORT of a running `dask scheduler`, or its scheduler file")
    host, _, port = rest.rpartition(":")
    bracketed = host.startswith("[") and host.endswith("]")  # an IPv6 literal
    host = host[1:-1] if bracketed else host
    if not host or not port.isascii() or not port.isdigit() or not 0 < int(port) < 65536 \
            or any(c in "/?#@[]" or c.isspace() for c in host) or (":" in host and not bracketed):
        raise _refuse(text, f"{address!r} is not HOST:PORT with a port in 1..65535{where}: e.g. tcp://127.0.0.1:8786")
    problem = None if bracketed else _host_name_problem(host)
    if problem is not None:
        raise _refuse(text, f"{problem}{where}: e.g. tcp://127.0.0.1:8786")
    return address, scheme, host, int(port)


def _read_scheduler_file(path: str) -> str:
    """The address in a scheduler file (JSON with ``"address"``, as ``dask scheduler --scheduler-file`` writes)."""
    hint = ("give the tcp://HOST:PORT or tls://HOST:PORT of a running `dask scheduler`, or the file written by "
            "`dask scheduler --scheduler-file FILE`")
    if not os.path.lexists(path):
        raise _refuse(path, f"no such scheduler file (and not an address): {hint}")
    if not os.path.isfile(path):  # a directory, a FIFO, a device: never opened
        raise _refuse(path, f"not a regular file: {hint}")
    try:
        with open(path, "rb") as handle:
            data = handle.read(_SCHEDULER_FILE_BYTES + 1)
    except OSError as exc:
        raise _refuse(path, f"cannot read the scheduler file ({exc.strerror or exc})") from None
    try:
        info = json.loads(data.decode("utf-8")) if len(data) <= _SCHEDULER_FILE_BYTES else None
    except (UnicodeDecodeError, ValueError):
        info = None
    address = info.get("address") if isinstance(info, dict) else None
    if not isinstance(address, str) or "://" not in address:
        what = "empty" if not data.strip() else "not a Dask scheduler file (JSON with an \"address\")"
        raise _refuse(path, f"the file is {what}: {hint}")
    return address


def _security(args: argparse.Namespace) -> Any:
    """Dask's ``Security`` from ``--tls-ca-file/--tls-cert/--tls-key``, else None (Dask's configuration)."""
    given = {name: getattr(args, name, None) for name in _TLS_OPTIONS}
    if not any(given.values()):
        return None
    missing = [f"--{name.replace('_', '-')}" for name in ("tls_ca_file", "tls_cert") if not given[name]]
    if missing:
        raise UsageError(f"{' and '.join(missing)} missing: a TLS client needs the cluster's CA "
                         "(--tls-ca-file) and its own certificate (--tls-cert, with --tls-key unless the key is in it)")
    for name, path in given.items():
        if path is not None and not os.path.isfile(path):
            raise UsageError(f"--{name.replace('_', '-')}={path}: no such file")
    from distributed.security import Security

    return Security(tls_ca_file=given["tls_ca_file"], tls_client_cert=given["tls_cert"],
                    tls_client_key=given["tls_key"], require_encryption=True)


def _quiet_dask() -> None:
    """Dask's own log lines off for this command (each failure is one line of ours)."""
    prefixes = ("distributed", "tornado", "asyncio")
    for name in [*prefixes, *logging.root.manager.loggerDict]:  # Dask's configuration sets its loggers' own levels
        if name.startswith(prefixes):
            logging.getLogger(name).setLevel(logging.CRITICAL + 1)


def _probe(address: str, scheme: str, host: str, port: int, security: Any) -> dict:
    """Dask's ``identity`` of the scheduler at ``address``, each step within :data:`CONNECT_SECONDS`."""
    import asyncio  # only for --scheduler: 10 ms of every command's start otherwise
    import ssl

    try:
        raw = socket.create_connection((host, port), timeout=CONNECT_SECONDS)
    except ConnectionRefusedError:
        raise _refuse(address, f"nothing listens at {host}:{port} (connection refused)") from None
    except socket.gaierror as exc:
        raise _refuse(address, f"unknown host {host!r} ({exc.strerror})") from None
    except TimeoutError:
        raise _refuse(address, f"no answer from {host}:{port} within {CONNECT_SECONDS:g} s") from None
    except OSError as exc:
        raise _refuse(address, f"cannot connect to {host}:{port} ({exc.strerror or exc})") from None
    context = security.get_connection_args("client")["ssl_context"]
    sock = raw
    try:
        raw.settimeout(CONNECT_SECONDS)
        if scheme == "tls":
            sock = context.wrap_socket(raw, server_hostname=None)
        head = _first_bytes(sock, 8)
    except ssl.SSLError as exc:
        raise _refuse(address, f"TLS refused ({exc.reason or exc}): the scheduler's certificate is not signed by "
                               "--tls-ca-file, or it refuses this client's certificate (--tls-cert)") from None
    except TimeoutError:
        plain = "; a TLS scheduler needs tls:// and certificates" if scheme == "tcp" else ""
        raise _refuse(address, f"the server at {host}:{port} said nothing within {CONNECT_SECONDS:g} s: not a Dask "
                               f"scheduler{plain}") from None
    except OSError as exc:
        raise _refuse(address, f"the connection to {host}:{port} failed ({exc.strerror or exc})") from None
    finally:
        sock.close()
    # a Dask server speaks first: its handshake, a message of a few frames (the count, 8 bytes little-endian)
    if len(head) < 8:
        raise _refuse(address, f"the server at {host}:{port} closed the connection: not a Dask scheduler")
    if not 0 < int.from_bytes(head, "little") <= 64:
        raise _refuse(address, f"the server at {host}:{port} speaks another protocol: not a Dask scheduler")

    async def identity() -> Any:
        from distributed.comm import connect

        comm = await connect(address, timeout=CONNECT_SECONDS, deserialize=False,
                             **security.get_connection_args("client"))
        try:
            await comm.write({"op": "identity", "reply": True})
            return await comm.read()
        finally:
            comm.abort()

    async def bounded() -> Any:
        return await asyncio.wait_for(identity(), CONNECT_SECONDS)

    try:
        info = asyncio.run(bounded())
    except Exception as exc:  # any failure of a stranger's reply is the same refusal
        timed_out = isinstance(exc, (TimeoutError, asyncio.TimeoutError))
        why = f"no answer within {CONNECT_SECONDS:g} s" if timed_out else f"{type(exc).__name__}"
        if scheme == "tls" and not timed_out:  # TLS 1.3: a refused client certificate shows after the handshake
            raise _refuse(address, f"the scheduler at {host}:{port} closed the connection ({why}): it refuses this "
                                   "client's certificate (--tls-cert), or it is not a Dask scheduler") from None
        plain = "; a TLS scheduler needs tls:// and certificates" if scheme == "tcp" else ""
        raise _refuse(address, f"no Dask scheduler answers at {host}:{port} ({why}{plain})") from None
    if not isinstance(info, dict) or info.get("type") != "Scheduler":
        raise _refuse(address, f"the server at {host}:{port} is not a Dask scheduler")
    return info


def _first_bytes(sock: socket.socket, count: int) -> bytes:
    """Up to ``count`` bytes from ``sock`` (fewer if it closes; its timeout applies)."""
    data = b""
    while len(data) < count:
        chunk = sock.recv(count - len(data))
        if not chunk:
            break
        data += chunk
    return data


def connect_scheduler(text: str, security: Any = None) -> Any:
    """A Dask client of the scheduler at ``text`` (``tcp://``/``tls://`` address or scheduler file), with a worker.

    ``security``: Dask's ``Security`` (None: Dask's configuration,
    ``distributed.comm.tls.*`` or ``DASK_DISTRIBUTED__COMM__TLS__*``).  Every
    step is bounded (:data:`CONNECT_SECONDS`, :data:`WORKER_SECONDS`); a wait
    for the first worker is announced on stderr.

    Raises
    ------
    UsageError
        One line naming the failure.
    """
    try:
        from distributed import Client
        from distributed.security import Security
    except ImportError:
        raise UsageError(DISTRIBUTED_MISSING) from None
    address, scheme, host, port = scheduler_address(text)
    _quiet_dask()
    try:
        security = Security() if security is None else security
        context = security.get_connection_args("client")["ssl_context"]
    except (OSError, ValueError) as exc:  # Dask's configuration names files that are not there or not certificates
        raise _refuse(text, f"Dask's TLS configuration cannot be used ({exc})") from None
    if scheme == "tls" and context is None:
        raise _refuse(text, "a TLS scheduler needs the cluster's CA and a client certificate: --tls-ca-file, "
                            "--tls-cert, --tls-key (or Dask's configuration distributed.comm.tls.ca-file, "
                            "distributed.comm.tls.client.cert, distributed.comm.tls.client.key)")
    if scheme == "tcp" and security.require_encryption:
        raise _refuse(text, "TLS certificates are given but the address is tcp://: use tls://")
    info = _probe(address, scheme, host, port, security)
    class BoundedClient(Client):
        """Dask's client whose ``close`` is bounded and silent (a run's own error, not the closing's, is reported)."""

        def close(self, timeout: float | None = None) -> Any:
            try:
                return super().close(timeout=CONNECT_SECONDS)
            except Exception:  # the scheduler gone already: nothing left to close
                return None

    try:
        client = BoundedClient(address, security=security, timeout=CONNECT_SECONDS, set_as_default=False)
    except Exception as exc:  # the probe answered; anything now is the same refusal
        raise _refuse(text, f"cannot connect ({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''})"
                      ) from None
    if not info.get("workers"):
        print(f"forcenet: the cluster at {address} has no worker yet: waiting up to {WORKER_SECONDS:g} s",
              file=sys.stderr, flush=True)
        try:
            client.wait_for_workers(1, timeout=WORKER_SECONDS)
        except Exception:  # a timeout, or the scheduler gone meanwhile
            client.close()
            raise _refuse(text, f"the cluster has no workers after {WORKER_SECONDS:g} s "
                                f"(start `dask worker {address}` with forcenet installed)") from None

    try:  # one tiny task: workers that cannot import forcenet are named now, not after the run's long wait
        check_cluster(client)
    except BaseException:
        client.close()
        raise
    return client


def add_engine_options(p: argparse.ArgumentParser, what: str) -> None:
    """``--scheduler`` (and its TLS), ``--checkpoint``, ``--no-checkpoint`` for a route over independent primes."""
    p.add_argument("--scheduler", metavar="ADDRESS",
                   help=f"run {what}'s per-prime tasks on a Dask cluster: the tcp://HOST:PORT or tls://HOST:PORT "
                        "of a running `dask scheduler`, or its scheduler file (workers need forcenet installed; "
                        "pip install 'forcenet[distributed]')")
    p.add_argument("--tls-ca-file", metavar="FILE", help="with --scheduler tls://...: the cluster's CA certificate "
                   "(default: Dask's configuration distributed.comm.tls.ca-file)")
    p.add_argument("--tls-cert", metavar="FILE", help="with --scheduler tls://...: this client's certificate "
                   "(default: distributed.comm.tls.client.cert)")
    p.add_argument("--tls-key", metavar="FILE", help="with --scheduler tls://...: this client's private key "
                   "(default: distributed.comm.tls.client.key, or in the certificate's file)")
    p.add_argument("--checkpoint", metavar="DIR",
                   help=f"record every finished prime of {what} in DIR; a rerun of the same request "
                        "recomputes only what is missing (default for runs announced at over a minute: "
                        "$XDG_CACHE_HOME/forcenet, else ~/.cache/forcenet)")
    p.add_argument("--no-checkpoint", action="store_true", help="no checkpoints, even for runs over a minute")


def engine_options(args: argparse.Namespace, applies: bool, what: str, plan_seconds: float,
                   store_for: Callable[[str], Any]) -> tuple[Any, Any]:
    """``(client or None, checkpoint store or None)`` from :func:`add_engine_options`' arguments.

    ``applies``: the chosen route runs over primes (else the options are refused, naming ``what``).  Runs
    announced at over a minute checkpoint by default in the user's cache directory; ``store_for(directory)``
    makes the request's store.
    """
    if args.checkpoint is not None and args.no_checkpoint:
        raise UsageError("--checkpoint and --no-checkpoint contradict each other: give one")
    tls = [f"--{name.replace('_', '-')}" for name in _TLS_OPTIONS if getattr(args, name, None) is not None]
    if tls and args.scheduler is None:
        raise UsageError(f"{', '.join(tls)} applies to --scheduler only (the client's TLS)")
    if not applies:
        for name in ("scheduler", "checkpoint"):
            if getattr(args, name) is not None:
                raise UsageError(f"--{name} applies to {what} only (the route over independent primes)")
        return None, None
    directory = args.checkpoint
    if directory is not None:
        check_output_dir(directory, "--checkpoint")
    elif not args.no_checkpoint and plan_seconds > FORCE_SECONDS:
        directory = default_directory()
    _check_apart(getattr(args, "out", None), directory)
    store = None if directory is None else store_for(directory)
    if args.scheduler is None:
        return None, store
    try:
        security = _security(args)
    except ImportError:
        raise UsageError(DISTRIBUTED_MISSING) from None
    return connect_scheduler(args.scheduler, security), store


def _check_apart(out: str | None, directory: str | None) -> None:
    """Refuse, before the run, an ``--out`` file that is the checkpoint folder or a folder holding it."""
    if out is None or directory is None:
        return
    file, folder = os.path.realpath(out), os.path.realpath(directory)
    if folder == file or folder.startswith(file.rstrip(os.sep) + os.sep):
        raise UsageError(f"--out={out} names the checkpoint folder {directory} (or a folder holding it): give "
                         "--out a file outside it")


def report_checkpoints(store: CheckpointStore | str, ticks: int) -> None:
    """The closing line on stderr about a run's checkpoints: a store's reuse, or the directory of a run with one
    request per layer (``store`` is then the directory itself)."""
    if isinstance(store, str):
        print(f"forcenet: checkpoints in {store} (one request per layer)", file=sys.stderr)
    else:
        print(f"forcenet: checkpoints in {store.path}: reused {store.reused} of {ticks} primes, "
              f"computed {ticks - store.reused}", file=sys.stderr)
