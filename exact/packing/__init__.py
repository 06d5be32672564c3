"""The N x P packing of Secs. 3.2-3.3, exactly, when every q is allowed.
"""

from .mobilized import mean_W_mobilized

__all__ = ["mean_W_mobilized"]
