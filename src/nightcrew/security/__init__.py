"""Who may do what: the observatory-wide access policy, the audit trail of state-changing calls, and
the hashed secrets people log in with (console, chat).

One YAML file (:func:`load_policy`) gives roles to accounts and rights to roles; every module's comm
names it (``comm: {policy: policy.yaml, audit: audit.jsonl}``) and the RPC server, the one place
where calls are dispatched, enforces it for every transport. See docs/security.md.
"""

from nightcrew.security._audit import AuditLog, AuditRecord, is_state_changing, read_audit
from nightcrew.security._passwords import (
    LoginLimiter,
    check_password_hash,
    dummy_password_hash,
    hash_password,
    verify_password,
)
from nightcrew.security._policy import (
    DEFAULT_SAFETY_METHODS,
    OPEN_POLICY,
    Policy,
    closed_policy,
    load_policy,
    parse_policy,
    starting_policy,
)
from nightcrew.security._throttle import WarningThrottle

__all__ = [
    "DEFAULT_SAFETY_METHODS",
    "OPEN_POLICY",
    "AuditLog",
    "AuditRecord",
    "LoginLimiter",
    "Policy",
    "WarningThrottle",
    "check_password_hash",
    "closed_policy",
    "dummy_password_hash",
    "hash_password",
    "is_state_changing",
    "load_policy",
    "parse_policy",
    "read_audit",
    "starting_policy",
    "verify_password",
]
