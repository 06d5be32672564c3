"""Three primes of the lattice directions at N (edge_residues), in-process: the kernel's cost as a whole process."""
import sys

from forcenet.exact.triangle.free_fermion.cost import route_primes
from forcenet.exact.triangle.free_fermion.engine import edge_residues

N = int(sys.argv[1])
for p in route_primes(N, 10**200)[:3]:
    edge_residues(N, p)
