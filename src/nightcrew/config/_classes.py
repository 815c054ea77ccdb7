"""Finding the class a configuration names, and the keys its constructor accepts.

Constructors forward ``**kwargs`` to their bases (``StandAlone(message, interval, **kwargs)`` →
``Module(name, comm, ...,  **kwargs)`` → ...), so the accepted keys of a class are the parameters of
its ``__init__`` plus, while an ``__init__`` takes ``**kwargs``, those of the next ``__init__`` in
the MRO. The chain stops at the first ``__init__`` without ``**kwargs``, or at ``object``.
"""

from __future__ import annotations

import difflib
import importlib
import inspect
import typing
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from nightcrew.config._paths import PathRole, path_role

__all__ = ["ClassResolutionError", "ConstructorSpec", "Parameter", "constructor_spec", "import_class"]


class ClassResolutionError(Exception):
    """A class path cannot be turned into a class; the caller adds file, line and key."""


@dataclass(frozen=True)
class Parameter:
    """One constructor parameter that a configuration key may set.

    Attributes:
        name: Parameter and key name.
        hint: Its type hint, ``typing.Any`` when it has none (or it cannot be evaluated here).
        required: Whether it has no default.
        owner: The class whose ``__init__`` declares it.
        path_role: Whether it takes a file path, and which kind (:mod:`._paths`); None: no path.
    """

    name: str
    hint: Any
    required: bool
    owner: type
    path_role: PathRole | None = None


@dataclass(frozen=True)
class ConstructorSpec:
    """The keys a class accepts.

    Attributes:
        cls: The class.
        parameters: Parameters by name, subclass first (a subclass's hint and default win).
        open_ended: Whether the chain ends in a constructor we cannot inspect (a C extension); then
            unknown keys cannot be told apart from valid ones and are let through.
    """

    cls: type
    parameters: Mapping[str, Parameter]
    open_ended: bool


def import_class(path: str) -> type:
    """The class at the dotted import path ``path`` (``package.module.Class``, or ``...Outer.Inner``).

    Raises:
        ClassResolutionError: With a message saying what is wrong with ``path``.
    """
    parts = path.split(".")
    if len(parts) < 2 or not all(part.isidentifier() for part in parts):
        raise ClassResolutionError(f"'{path}' is not a dotted class path like 'package.module.Class'")
    first_missing: tuple[str, ModuleNotFoundError] | None = None
    # Try the longest module prefix first; shorter ones allow classes nested in classes.
    for split in range(len(parts) - 1, 0, -1):
        module_name = ".".join(parts[:split])
        try:
            module = importlib.import_module(module_name)
        except ModuleNotFoundError as exc:
            if exc.name and (module_name == exc.name or module_name.startswith(exc.name + ".")):
                first_missing = first_missing or (module_name, exc)
                continue
            # The module exists but imports something that does not.
            raise ClassResolutionError(f"cannot import '{module_name}': {exc}") from exc
        except Exception as exc:
            raise ClassResolutionError(
                f"importing '{module_name}' failed: {type(exc).__name__}: {exc}"
            ) from exc
        found = _attribute_path(module, module_name, parts[split:], first_missing)
        if not isinstance(found, type):
            raise ClassResolutionError(f"'{path}' is not a class but a {type(found).__name__}")
        return found
    assert first_missing is not None
    raise ClassResolutionError(f"cannot import '{first_missing[0]}': {first_missing[1]}")


def _attribute_path(
    module: object, module_name: str, names: list[str], first_missing: tuple[str, ModuleNotFoundError] | None
) -> object:
    found = module
    where = module_name
    for name in names:
        try:
            found = getattr(found, name)
        except AttributeError:
            if first_missing is not None:
                # "no module a.b.c" says more than "module a.b has no attribute c".
                raise ClassResolutionError(
                    f"cannot import '{first_missing[0]}': {first_missing[1]}"
                ) from None
            candidates = [n for n in dir(found) if not n.startswith("_")]
            close = difflib.get_close_matches(name, candidates, n=1)
            hint = f" (did you mean '{close[0]}'?)" if close else ""
            raise ClassResolutionError(f"'{where}' has no attribute '{name}'{hint}") from None
        where = f"{where}.{name}"
    return found


def constructor_spec(cls: type) -> ConstructorSpec:
    """The configuration keys ``cls`` accepts, following ``**kwargs`` up the MRO."""
    parameters: dict[str, Parameter] = {}
    mro = cls.__mro__
    start = 0
    while True:
        owner_index = next((i for i in range(start, len(mro)) if "__init__" in vars(mro[i])), None)
        if owner_index is None or mro[owner_index] is object:
            return ConstructorSpec(cls, parameters, open_ended=False)
        owner = mro[owner_index]
        init = vars(owner)["__init__"]
        if not inspect.isfunction(init):
            return ConstructorSpec(cls, parameters, open_ended=True)
        forwards_kwargs = _add_parameters(parameters, init, owner)
        if not forwards_kwargs:
            return ConstructorSpec(cls, parameters, open_ended=False)
        start = owner_index + 1


def _add_parameters(parameters: dict[str, Parameter], init: Callable[..., Any], owner: type) -> bool:
    """Add the keyword parameters of ``init``; returns whether it takes ``**kwargs``."""
    hints = _parameter_hints(init)
    roles = _path_roles(init)
    forwards_kwargs = False
    for index, param in enumerate(inspect.signature(init).parameters.values()):
        if index == 0 or param.kind is param.VAR_POSITIONAL or param.kind is param.POSITIONAL_ONLY:
            continue  # self, *args and positional-only parameters cannot be set by a key
        if param.kind is param.VAR_KEYWORD:
            forwards_kwargs = True
            continue
        parameters.setdefault(
            param.name,
            Parameter(
                param.name,
                hints.get(param.name, Any),
                param.default is param.empty,
                owner,
                roles.get(param.name),
            ),
        )
    return forwards_kwargs


def _path_roles(init: Callable[..., Any]) -> dict[str, PathRole]:
    """The parameters of ``init`` hinted :data:`InputPath` / :data:`DataPath` (their extras are
    gone from the hints the validator reads)."""
    try:
        hints = typing.get_type_hints(init, include_extras=True)
    except Exception:
        return {}
    roles = {name: path_role(hint) for name, hint in hints.items()}
    return {name: role for name, role in roles.items() if role is not None}


def _parameter_hints(init: Callable[..., Any]) -> dict[str, Any]:
    try:
        # With extras: bounds declared with Annotated (interfaces.quantities) are checked too.
        return typing.get_type_hints(init, include_extras=True)
    except Exception:
        pass
    # Some annotation cannot be evaluated here (e.g. a name imported only under TYPE_CHECKING):
    # evaluate the others one by one and let the failing ones accept anything.
    hints: dict[str, Any] = {}
    namespace = getattr(init, "__globals__", {})
    for name, annotation in getattr(init, "__annotations__", {}).items():
        if not isinstance(annotation, str):
            hints[name] = annotation
            continue
        try:
            hints[name] = eval(annotation, namespace)
        except Exception:
            hints[name] = Any
    return hints
