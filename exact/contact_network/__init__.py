"""Any contact network (thesis Sec. 2.3): the model, the ensemble's polytope, exact moments through Normaliz."""
