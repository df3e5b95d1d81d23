"""Scan -> Body -> rocking parameters: reading, repair, units, orientation, mass
properties, footprint and the rocking parameters of the base."""
