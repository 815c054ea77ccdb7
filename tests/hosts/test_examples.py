"""The multi-host examples validate and build (the multi-host test runs them for real)."""

from __future__ import annotations

from pathlib import Path

import pytest

from nightcrew.config import build_object, load_config, validate_config
from nightcrew.modules import Module
from nightcrew.server import create_missing_passwords
from nightcrew.vfs import SMBFile, SSHFile

REPOSITORY = Path(__file__).resolve().parents[2]
EXAMPLES = REPOSITORY / "examples" / "multi-host"
ENVIRONMENT = {
    "SIM_XMPP_CA_FILE": str(REPOSITORY / "pyproject.toml"),  # any file: building checks it exists
    "SIM_XMPP_POLICY": str(REPOSITORY / "examples" / "notify" / "policy.yaml"),  # any policy
    "NC_FILECACHE_TOKEN": "cache-token",
    "NC_FILECACHE_URL": "http://10.0.0.2:37081",
    "NC_SSH_HOST": "dome.example",
    "NC_SSH_ROOT": "/srv/frames",
    "NC_SSH_KEY": "/home/nightcrew/.ssh/id_ed25519",
    "NC_SSH_KNOWN_HOSTS": "/home/nightcrew/.ssh/known_hosts",
    "NC_SMB_HOST": "dome.example",
    "NC_SMB_PASSWORD": "pw",
}


@pytest.fixture(autouse=True)
def passwords(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """The accounts' passwords, as docs/operations.md's `nightcrew server init` (step 2) makes them."""
    monkeypatch.setitem(ENVIRONMENT, "SIM_XMPP_SECRETS", str(tmp_path / "secrets"))
    files = [*sorted((EXAMPLES.parent / "sim-processes").glob("*.yaml")), *sorted(EXAMPLES.glob("*.yaml"))]
    create_missing_passwords(files, environ=ENVIRONMENT)


@pytest.mark.parametrize("path", sorted(EXAMPLES.glob("*.yaml")), ids=lambda p: p.name)
def test_example_validates_and_builds(path: Path) -> None:
    config = load_config(path, environ=ENVIRONMENT)
    validate_config(config, Module)
    module = build_object({**config, "name": path.stem}, Module)
    assert isinstance(module, Module)


def test_the_writers_use_the_remote_roots() -> None:
    roots = {}
    for name in ("writer-ssh", "writer-smb"):
        config = load_config(EXAMPLES / f"{name}.yaml", environ=ENVIRONMENT)
        module = build_object({**config, "name": name}, Module)
        roots.update(module.vfs.roots)
    ssh, smb = roots["dome"], roots["share"]
    assert isinstance(ssh, SSHFile) and (ssh.host, ssh.port, ssh.root) == ("dome.example", 22, "/srv/frames")
    assert isinstance(smb, SMBFile) and (smb.host, smb.port, smb.share, smb.root) == (
        "dome.example",
        445,
        "images",
        "",
    )
