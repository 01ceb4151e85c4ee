"""Drying paste (SPH): initial state, run, and analysis of a thin visco-elastic layer under a
drying stress (drying spec). The model API used by the CLI is in :mod:`craquelure.drying.api`."""
