"""A self-signed certificate for a private server (made with the ``openssl`` command)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from nightcrew.errors import NightcrewError

__all__ = ["make_self_signed"]


def make_self_signed(cert_dir: Path, domain: str) -> tuple[Path, Path]:
    """Write ``<domain>.crt`` and ``<domain>.key`` valid for the domain and its MUC service.

    Returns the certificate and key paths. Clients trust the certificate with ``ca_file``.
    """
    if shutil.which("openssl") is None:
        raise NightcrewError("the openssl command is needed to make a TLS certificate")
    cert_dir.mkdir(parents=True, exist_ok=True)
    cert, key = cert_dir / f"{domain}.crt", cert_dir / f"{domain}.key"
    subprocess.run(
        [
            "openssl", "req", "-x509", "-nodes", "-days", "3650",
            "-newkey", "ec", "-pkeyopt", "ec_paramgen_curve:prime256v1",
            "-keyout", str(key), "-out", str(cert),
            "-subj", f"/CN={domain}",
            "-addext", f"subjectAltName=DNS:{domain},DNS:conference.{domain}",
            "-addext", "basicConstraints=critical,CA:TRUE",
        ],
        check=True,
        capture_output=True,
    )  # fmt: skip
    key.chmod(0o600)
    return cert, key
