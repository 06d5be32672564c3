"""Clusters of large forces and their finite-size scaling (thesis Part III, Chs. 6-7).

:mod:`.newman_ziff` (every threshold's clusters in one compiled pass), :mod:`.finite_size_scaling` (the
collapse (6.12) and the standard estimators with bootstrap errors), :mod:`.q_models` (Sec. 7.3) and
:mod:`.engines` (the models as registry engines).  The front door is :func:`forcenet.clusters` and
:func:`forcenet.scaling`.
"""
