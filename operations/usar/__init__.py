"""The UvA adaptive indoor map generator (Zwennes 2011): catalogue, grid layout, plan.

:mod:`.catalogue` reads the room catalogue, :mod:`.generator` lays out the grid by the
paper's five rules, :mod:`.plan` turns the grid into a typed floor plan.
"""
