"""The wall failure laws, one module each, registered in :data:`impactdyn.wall.FAILURE_LAWS`
(:mod:`impactdyn.wall._failure_law` says what a law brings):

* :mod:`._tuler_butcher` — ``"tuler_butcher"`` (the default), the cumulative damage of the mean tension
  over a threshold;
* :mod:`._cutoff` — ``"cutoff"``, the instantaneous pressure cut-off p < −p_spall.

A new law is one more module here (docs/extending.md), or one registered from the user's own code.
"""

# imported in the order their names are listed (the default first); each registers itself
from impactdyn.wall.failure_laws import _tuler_butcher  # noqa: F401  isort: skip
from impactdyn.wall.failure_laws import _cutoff  # noqa: F401  isort: skip
