"""Simulator (later issues): runs the same step functions on the float backend."""
