"""forcenet: exact enumeration and Monte Carlo for the force network ensemble.

The exact API lives in :mod:`exact`, the samplers in :mod:`numeric`; this
package holds the command line interface.
"""

__version__ = "0.1.0"
