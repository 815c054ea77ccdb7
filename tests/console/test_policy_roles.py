"""Console roles on the access policy: the console calls as ``console:viewer`` or ``console:operator``
and the module called decides with the policy (ForbiddenError), over real HTTP to the running console.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

from nightcrew.comm.local import LocalComm
from nightcrew.modules.sim import SimRoof
from nightcrew.security import read_audit

from .conftest import OPERATOR, OPERATOR_PASSWORD, VIEWER, VIEWER_PASSWORD, ApiClient, Observatory

POLICY = """\
roles:
  reader: ["*.get_*", "*.is_*", IModule]
  operator: ["*"]
accounts:
  console: [reader]              # the console's own status polls
  "console:viewer": [reader]     # a logged-in viewer
  "console:operator": [operator] # a logged-in operator
"""


class _SecuredObservatory(Observatory):
    def __init__(self, policy: Path, audit: Path) -> None:
        super().__init__(speed=100.0)
        self.policy, self.audit = policy, audit

    def comm(self, name: str) -> LocalComm:
        return LocalComm(name, network=self.network, policy=str(self.policy), audit=str(self.audit))


async def test_viewer_is_refused_by_the_module_and_operator_is_not(
    tmp_path: Path, clients: Callable[[str], ApiClient]
) -> None:
    (tmp_path / "policy.yaml").write_text(POLICY)
    observatory = _SecuredObservatory(tmp_path / "policy.yaml", tmp_path / "audit.jsonl")
    try:
        roof = await observatory.start(SimRoof, "roof", open_time=1.0)
        console = await observatory.start_console()
        viewer, operator = clients(console.url), clients(console.url)
        assert (await viewer.login(VIEWER, VIEWER_PASSWORD))[0] == 200
        assert (await operator.login(OPERATOR, OPERATOR_PASSWORD))[0] == 200

        assert await viewer.call("roof", "get_motion_status") == (200, {"result": "parked"})
        for status, body in (
            await viewer.call("roof", "open_roof"),
            await viewer.post("/api/shell", {"line": "roof.open_roof()"}),
        ):
            assert status == 403, body
            assert body["error"]["class"] == "ForbiddenError" and body["error"]["module"] == "roof"
            assert "console:viewer may not call roof.open_roof()" in body["error"]["message"]
        assert roof.opened == 0.0

        assert await operator.call("roof", "open_roof") == (200, {"result": None})
        assert roof.opened == 1.0
        calls = [(r.caller, r.method, r.outcome) for r in read_audit(tmp_path / "audit.jsonl")]
        assert ("console:viewer", "open_roof", "forbidden") in calls
        assert ("console:operator", "open_roof", "ok") in calls
    finally:
        await observatory.close()
