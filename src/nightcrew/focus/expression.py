"""Safe arithmetic expressions from configuration, e.g. a focus model ``a*T1 + b*T2 + c``.

The text is parsed with :mod:`ast` and only a whitelist of node kinds is accepted: numbers, names,
``+ - * /``, powers (``^`` or ``**``), unary minus/plus, parentheses and calls of the functions in
:data:`FUNCTIONS` by their bare name. Anything else (attribute access, subscripts, strings,
lambdas, comparisons, calls of other names, ``__import__`` ...) is refused when the expression is
built, with :class:`ExpressionError` saying what and where. Python's ``eval`` is never used: the
checked tree is walked by :meth:`Expression.evaluate` with plain float arithmetic.

Numbers are floats (so ``9^9^9`` overflows to an error instead of building a huge integer), and
arithmetic failures (division by zero, overflow, log of a negative number) raise ExpressionError.

>>> Expression("a*T + b").evaluate({"a": -0.05, "T": 10.0, "b": 25.0})
24.5
>>> sorted(Expression("exp(-1.22*(h + 4.07))").names)
['h']
"""

from __future__ import annotations

import ast
import math
from collections.abc import Callable, Mapping
from typing import Final

from nightcrew.errors import InvalidArgumentError

__all__ = ["FUNCTIONS", "Expression", "ExpressionError", "coefficient_degree"]

#: Functions an expression may call, each with one argument.
FUNCTIONS: Final[Mapping[str, Callable[[float], float]]] = {
    "exp": math.exp,
    "log": math.log,
    "log10": math.log10,
    "sqrt": math.sqrt,
    "abs": abs,
    "sin": math.sin,
    "cos": math.cos,
    "tan": math.tan,
}

#: Longest accepted text; deeper nesting than the parser can take is refused as well.
MAX_LENGTH: Final = 2000

_BINARY: Final[Mapping[type[ast.operator], Callable[[float, float], float]]] = {
    ast.Add: lambda x, y: x + y,
    ast.Sub: lambda x, y: x - y,
    ast.Mult: lambda x, y: x * y,
    ast.Div: lambda x, y: x / y,
    ast.Pow: math.pow,  # real powers only: a negative base with a fractional exponent raises
}


class ExpressionError(InvalidArgumentError):
    """An expression cannot be parsed, uses something not allowed, or cannot be evaluated."""


class Expression:
    """A checked arithmetic expression over named variables.

    Args:
        text: The formula, e.g. ``a*T_mirror + b*T_tube + c`` or ``exp(-1.22*(h + 4.07))``.

    Raises:
        ExpressionError: The text is not a formula of the allowed kind (the message says why).
    """

    def __init__(self, text: str) -> None:
        if not isinstance(text, str) or not text.strip():
            raise ExpressionError("an expression must be a non-empty string")
        if len(text) > MAX_LENGTH:
            raise ExpressionError(f"expression longer than {MAX_LENGTH} characters")
        try:
            # Python's "^" is XOR with a low precedence; "**" gives "-x^2" and "a*T^2" their usual meaning.
            tree = ast.parse(text.strip().replace("^", "**"), mode="eval")
        except (SyntaxError, ValueError, RecursionError, MemoryError) as exc:
            raise ExpressionError(f"cannot parse expression {text!r}: {exc}") from None
        names: set[str] = set()
        try:
            _check(tree.body, names)
        except RecursionError:
            raise ExpressionError(f"expression {text!r} is nested too deeply") from None
        self.text = text.strip()
        self._body = tree.body
        #: Variable names the expression reads (function names excluded).
        self.names: frozenset[str] = frozenset(names)

    def __repr__(self) -> str:
        return f"Expression({self.text!r})"

    def __str__(self) -> str:
        return self.text

    def evaluate(self, values: Mapping[str, float]) -> float:
        """The value for the given variables; every name in :attr:`names` must be given.

        Raises:
            ExpressionError: A variable is missing or the arithmetic fails.
        """
        missing = sorted(self.names - set(values))
        if missing:
            raise ExpressionError(f"no value for {', '.join(missing)} in {self.text!r}")
        try:
            result = _evaluate(self._body, values)
        except (ArithmeticError, ValueError) as exc:
            raise ExpressionError(f"cannot evaluate {self.text!r}: {exc}") from None
        if not math.isfinite(result):
            raise ExpressionError(f"{self.text!r} is not finite ({result}) for {dict(values)}")
        return result


def _where(node: ast.AST) -> str:
    return f"at column {getattr(node, 'col_offset', 0) + 1}"


def _check(node: ast.expr, names: set[str]) -> None:
    """Refuse every node that is not a number, name, arithmetic or whitelisted call."""
    if isinstance(node, ast.Constant):
        if isinstance(node.value, bool) or not isinstance(node.value, int | float):
            raise ExpressionError(f"only numbers are allowed as constants, got {node.value!r} {_where(node)}")
    elif isinstance(node, ast.Name):
        if node.id.startswith("_"):
            raise ExpressionError(f"names starting with '_' are not allowed: {node.id!r} {_where(node)}")
        if node.id in FUNCTIONS:
            raise ExpressionError(f"function {node.id!r} used without arguments {_where(node)}")
        names.add(node.id)
    elif isinstance(node, ast.BinOp):
        if type(node.op) not in _BINARY:
            raise ExpressionError(f"operator {type(node.op).__name__} is not allowed {_where(node)}")
        _check(node.left, names)
        _check(node.right, names)
    elif isinstance(node, ast.UnaryOp):
        if not isinstance(node.op, ast.USub | ast.UAdd):
            raise ExpressionError(f"operator {type(node.op).__name__} is not allowed {_where(node)}")
        _check(node.operand, names)
    elif isinstance(node, ast.Call):
        if isinstance(node.func, ast.Attribute):
            _check(node.func, names)
        if not isinstance(node.func, ast.Name):
            raise ExpressionError(f"only plain function names may be called {_where(node)}")
        if node.func.id not in FUNCTIONS:
            allowed = ", ".join(sorted(FUNCTIONS))
            raise ExpressionError(
                f"calling {node.func.id!r} is not allowed {_where(node)}; allowed functions: {allowed}"
            )
        if node.keywords or len(node.args) != 1 or isinstance(node.args[0], ast.Starred):
            raise ExpressionError(f"{node.func.id}() takes exactly one argument {_where(node)}")
        _check(node.args[0], names)
    elif isinstance(node, ast.Attribute):
        raise ExpressionError(f"attribute access ('.{node.attr}') is not allowed {_where(node)}")
    else:
        raise ExpressionError(f"{type(node).__name__} is not allowed in an expression {_where(node)}")


def _evaluate(node: ast.expr, values: Mapping[str, float]) -> float:
    # Only node kinds accepted by _check reach this point.
    if isinstance(node, ast.Constant) and isinstance(node.value, int | float):
        return float(node.value)
    if isinstance(node, ast.Name):
        return float(values[node.id])
    if isinstance(node, ast.BinOp):
        return _BINARY[type(node.op)](_evaluate(node.left, values), _evaluate(node.right, values))
    if isinstance(node, ast.UnaryOp):
        operand = _evaluate(node.operand, values)
        return -operand if isinstance(node.op, ast.USub) else operand
    if isinstance(node, ast.Call) and isinstance(node.func, ast.Name):
        return float(FUNCTIONS[node.func.id](_evaluate(node.args[0], values)))
    raise ExpressionError(f"unexpected {type(node).__name__}")  # unreachable after _check


def coefficient_degree(expression: Expression, coefficients: frozenset[str] | set[str]) -> int:
    """The degree of ``expression`` as a polynomial in ``coefficients``: 0, 1, or 2 for "more".

    A model is linear in its coefficients (degree <= 1) when it is a sum of terms each multiplied by
    at most one coefficient, e.g. ``a*T1 + b*(T2 - T1) + c``. Coefficients inside a function, a
    power or a denominator, or multiplied together, make it non-linear (degree 2 is returned as
    soon as that is found).
    """
    return _degree(expression._body, coefficients)


def _degree(node: ast.expr, coefficients: frozenset[str] | set[str]) -> int:
    if isinstance(node, ast.Constant):
        return 0
    if isinstance(node, ast.Name):
        return 1 if node.id in coefficients else 0
    if isinstance(node, ast.UnaryOp):
        return _degree(node.operand, coefficients)
    if isinstance(node, ast.BinOp):
        left, right = _degree(node.left, coefficients), _degree(node.right, coefficients)
        if isinstance(node.op, ast.Add | ast.Sub):
            return max(left, right)
        if isinstance(node.op, ast.Mult):
            return min(2, left + right)
        if isinstance(node.op, ast.Div):
            return left if right == 0 else 2
        return 0 if left == right == 0 else 2  # powers
    if isinstance(node, ast.Call):
        return 0 if _degree(node.args[0], coefficients) == 0 else 2
    return 2
