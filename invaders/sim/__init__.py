"""The game as a pure simulation: no display, no clock, one seeded random generator."""
