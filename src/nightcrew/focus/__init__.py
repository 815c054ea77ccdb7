"""Focus algorithms, pure: safe model expressions, least-squares coefficient fits, focus history."""

from nightcrew.focus.expression import FUNCTIONS, Expression, ExpressionError, coefficient_degree
from nightcrew.focus.fit import CoefficientFit, check_linear, fit_coefficients
from nightcrew.focus.history import FocusRecord, records_from_plain, records_to_plain
from nightcrew.focus.series import FocusFit, FocusOutsideSeriesError, FocusSeriesError, fit_focus_hyperbola

__all__ = [
    "FUNCTIONS",
    "CoefficientFit",
    "Expression",
    "ExpressionError",
    "FocusFit",
    "FocusOutsideSeriesError",
    "FocusRecord",
    "FocusSeriesError",
    "check_linear",
    "coefficient_degree",
    "fit_coefficients",
    "fit_focus_hyperbola",
    "records_from_plain",
    "records_to_plain",
]
