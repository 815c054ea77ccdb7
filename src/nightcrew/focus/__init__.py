"""Focus algorithms, pure: safe model expressions, least-squares coefficient fits, focus history."""

from nightcrew.focus.expression import FUNCTIONS, Expression, ExpressionError, coefficient_degree
from nightcrew.focus.fit import CoefficientFit, check_linear, fit_coefficients
from nightcrew.focus.history import FocusRecord, records_from_plain, records_to_plain

__all__ = [
    "FUNCTIONS",
    "CoefficientFit",
    "Expression",
    "ExpressionError",
    "FocusRecord",
    "check_linear",
    "coefficient_degree",
    "fit_coefficients",
    "records_from_plain",
    "records_to_plain",
]
