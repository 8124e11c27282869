"""Furniture: the model library and the placement of items in typed rooms (docs/furniture.md)."""
