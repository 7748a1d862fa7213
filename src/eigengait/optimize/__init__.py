"""Optimization of pulse controllers: objective, batched evaluation, method of multipliers around
CMA-ES."""
