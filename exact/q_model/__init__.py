"""The microcanonical q-model's flow polytope, exactly (Sec. 7.3.2): :mod:`.flow_polytope`."""
