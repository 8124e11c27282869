"""The operation library: one module per grammar operation (docs/architecture.md,
"Operations").

Each module defines an :class:`~cga.operation.Operation` subclass; the engine finds them
through :data:`cga.registry.DEFAULT_OPERATIONS`, importing each on first use, so
``cga check`` never pays for the geometry and physics libraries the floor operations need.
"""
