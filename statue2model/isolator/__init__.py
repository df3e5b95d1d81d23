"""Seismic isolator design: response spectra and the models built on them."""
