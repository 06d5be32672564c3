"""Samplers of the force network ensemble on any contact network (hit-and-run)."""
