"""Survey of the chicken-wire <-> square-triangle correspondence on small tori (notes/chicken_wire.md, Sec. 7).

Run:  python benchmarks/tiling_survey.py 18 60 2x2 2x3 3x3 3x4 4x4 3x5 2x6 5x5 6x6 7x7
      (max tiling vertices to enumerate, seconds per lattice, tori)
Prints, per torus: configurations, in the image, failures (= formula), period lattices,
classes up to translation on both sides, matched.
"""

import sys

from forcenet.exact.chicken_wire.survey import survey


if __name__ == "__main__":
    vmax, seconds = int(sys.argv[1]), float(sys.argv[2])
    for spec in sys.argv[3:]:
        L, M = (int(x) for x in spec.split("x"))
        print(spec, survey(L, M, vmax, seconds), flush=True)
