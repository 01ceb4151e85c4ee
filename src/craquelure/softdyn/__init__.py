"""Soft Dynamics (softdyn spec): elastic spheres in a viscous fluid, lubrication in series with a
Hertz-like elastic response, overdamped force balance, and the T1 of four spheres."""
