"""Behaviours: small state machines turning the laser and the world model into base references."""
