"""The safe expression evaluator: arithmetic right, anything else refused with a clear message."""

from __future__ import annotations

import math

import pytest

from nightcrew.focus import Expression, ExpressionError, coefficient_degree


@pytest.mark.parametrize(
    ("text", "values", "expected"),
    [
        ("a*T + b", {"a": -0.05, "T": 10.0, "b": 25.0}, 24.5),
        ("-x^2", {"x": 3.0}, -9.0),  # unary minus binds looser than the power, as in maths
        ("2^3^2", {}, 512.0),  # powers are right-associative
        ("2**3", {}, 8.0),
        ("a*T^2", {"a": 2.0, "T": 3.0}, 18.0),
        ("(1 + 2) * 3 / 4 - -1", {}, 3.25),
        ("exp(-1.22*(h + 4.07))", {"h": -4.07}, 1.0),
        ("log(exp(2)) + log10(100) + sqrt(16) + abs(-1)", {}, 9.0),
        ("sin(0) + cos(0) + tan(0)", {}, 1.0),
        ("1e-3 * T_mirror", {"T_mirror": 2000.0}, 2.0),
    ],
)
def test_arithmetic(text: str, values: dict[str, float], expected: float) -> None:
    assert Expression(text).evaluate(values) == pytest.approx(expected)


def test_names_are_the_variables_without_functions() -> None:
    assert Expression("a*exp(T1) + b*sqrt(T2) + c").names == {"a", "b", "c", "T1", "T2"}


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("__import__('os').system('true')", r"attribute access \('.system'\) is not allowed"),
        ("__import__('os')", r"calling '__import__' is not allowed"),
        ("__builtins__", r"names starting with '_' are not allowed"),
        ("os.system('true')", r"attribute access \('.system'\) is not allowed"),
        ("(lambda: 1)()", r"only plain function names may be called"),
        ("x.real", r"attribute access \('.real'\) is not allowed"),
        ("().__class__", r"attribute access \('.__class__'\) is not allowed"),
        ("open('/etc/passwd')", r"calling 'open' is not allowed at column 1; allowed functions: abs, cos"),
        ("eval('1')", r"calling 'eval' is not allowed"),
        ("x[0]", r"Subscript is not allowed"),
        ("'text'", r"only numbers are allowed as constants"),
        ("True + 1", r"only numbers are allowed as constants"),
        ("lambda: 1", r"Lambda is not allowed"),
        ("x if y else z", r"IfExp is not allowed"),
        ("a < b", r"Compare is not allowed"),
        ("a % b", r"operator Mod is not allowed"),
        ("~a", r"operator Invert is not allowed"),
        ("exp(x, y)", r"exp\(\) takes exactly one argument"),
        ("exp(x=1)", r"exp\(\) takes exactly one argument"),
        ("exp + 1", r"function 'exp' used without arguments"),
        ("a = 1", r"cannot parse expression"),
        ("a +", r"cannot parse expression"),
        ("", r"non-empty string"),
        ("(" * 400 + "1" + ")" * 400, r"cannot parse|nested too deeply"),
        ("1+" * 1500 + "1", r"longer than 2000 characters"),
    ],
)
def test_unsafe_or_unknown_input_is_refused_clearly(text: str, message: str) -> None:
    with pytest.raises(ExpressionError, match=message):
        Expression(text)


@pytest.mark.parametrize(
    ("text", "values", "message"),
    [
        ("1/x", {"x": 0.0}, r"cannot evaluate '1/x': float division by zero"),
        ("9^9^9", {}, r"cannot evaluate '9\^9\^9'"),
        ("exp(x)", {"x": 1000.0}, r"cannot evaluate 'exp\(x\)'"),
        ("log(x)", {"x": -1.0}, r"cannot evaluate 'log\(x\)'"),
        ("(-8)^(1/3)", {}, r"cannot evaluate"),  # no complex numbers
        ("a*T", {"a": 1.0}, r"no value for T in 'a\*T'"),
    ],
)
def test_evaluation_failures_are_expression_errors(text: str, values: dict[str, float], message: str) -> None:
    with pytest.raises(ExpressionError, match=message):
        Expression(text).evaluate(values)


def test_infinite_input_is_refused() -> None:
    with pytest.raises(ExpressionError, match="not finite"):
        Expression("a*T").evaluate({"a": 1.0, "T": math.inf})


@pytest.mark.parametrize(
    ("text", "degree"),
    [
        ("T1 + 2*T2", 0),
        ("a*T1 + b*T2 + c*temp + d", 1),
        ("a*(T1 - T2) + T1*b/2 - c", 1),
        ("-a*exp(T) + b", 1),
        ("a*b*T", 2),
        ("exp(a*T)", 2),
        ("T^a", 2),
        ("T/a", 2),
        ("a^2", 2),
    ],
)
def test_degree_in_coefficients(text: str, degree: int) -> None:
    assert coefficient_degree(Expression(text), {"a", "b", "c", "d"}) == degree
