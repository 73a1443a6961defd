"""Hand-made observations for store tests (the truth is known because we made it)."""
from sg3d.testing import graph, hist_of, obj  # noqa: F401 - the test modules import them from here
