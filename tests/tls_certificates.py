"""Certificates for a TLS cluster on loopback, made in the test by the ``openssl`` command: a CA, certificates
signed by it, and a stranger's CA and certificate (nothing fetched, nothing kept beyond the test's folder)."""

import shutil
import subprocess
from pathlib import Path

OPENSSL = shutil.which("openssl")
_KEY = ["-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1", "-nodes"]


def _run(*args: str, cwd: Path) -> None:
    subprocess.run([OPENSSL, *args], cwd=cwd, check=True, capture_output=True, timeout=60)


def make_certificates(folder: Path) -> dict[str, tuple[str, str]]:
    """``{"ca": (crt, key), "node": ..., "client": ..., "stranger_ca": ..., "stranger": ...}`` in ``folder``:
    ``node`` and ``client`` signed by ``ca``, ``stranger`` by ``stranger_ca``; every leaf valid for 127.0.0.1."""
    (folder / "leaf.ext").write_text("basicConstraints=critical,CA:FALSE\nsubjectAltName=IP:127.0.0.1\n")
    out = {}
    for ca, leaves in (("ca", ("node", "client")), ("stranger_ca", ("stranger",))):
        _run("req", "-x509", *_KEY, "-keyout", f"{ca}.key", "-out", f"{ca}.crt", "-subj", f"/CN=forcenet test {ca}",
             "-days", "1", cwd=folder)
        out[ca] = (str(folder / f"{ca}.crt"), str(folder / f"{ca}.key"))
        for leaf in leaves:
            _run("req", *_KEY, "-keyout", f"{leaf}.key", "-out", f"{leaf}.csr", "-subj", f"/CN=forcenet test {leaf}",
                 cwd=folder)
            _run("x509", "-req", "-in", f"{leaf}.csr", "-CA", f"{ca}.crt", "-CAkey", f"{ca}.key", "-CAcreateserial",
                 "-out", f"{leaf}.crt", "-days", "1", "-extfile", "leaf.ext", cwd=folder)
            out[leaf] = (str(folder / f"{leaf}.crt"), str(folder / f"{leaf}.key"))
    return out
