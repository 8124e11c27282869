"""Measured difficulty of a build for a robot (DESIGN §13, docs/difficulty.md)."""

from .metrics import METRICS, DifficultyReport, FloorDifficulty, mean_metrics, measure_floor, measure_scene

__all__ = ["METRICS", "DifficultyReport", "FloorDifficulty", "mean_metrics", "measure_floor",
           "measure_scene"]
