"""An independent validator of UvA grid layouts (cga.operations.usar.generator): checks
from the cells, the rectangles and the links alone, without the generator's helpers."""

from __future__ import annotations

import networkx as nx
import numpy as np

HALL, CUT, OPEN = -1, -2, -3


def _touching(a: tuple[int, int, int, int], b: tuple[int, int, int, int],
              at: tuple[float, float]) -> bool:
    """Whether ``at`` lies on a shared edge of positive length of rectangles a and b."""
    ax0, ay0, ax1, ay1 = a
    bx0, by0, bx1, by1 = b
    x, y = at
    for line in {ax0, ax1} & {bx0, bx1}:
        if x == line and max(ay0, by0) < y < min(ay1, by1) and (ax0 == line) != (bx0 == line):
            return True
    for line in {ay0, ay1} & {by0, by1}:
        if y == line and max(ax0, bx0) < x < min(ax1, bx1) and (ay0 == line) != (by0 == line):
            return True
    return False


def validate_layout(layout) -> None:
    """Regions tile the grid once; rooms sit on their cells; every link joins two
    regions through their shared wall; no opening passes a removed hallway cell."""
    covered = np.zeros(layout.cells.shape, dtype=int)
    rects = {}
    for region in layout.regions:
        x0, y0, x1, y1 = region.rect
        assert x1 > x0 and y1 > y0
        covered[y0:y1, x0:x1] += 1
        rects[region.number] = region.rect
        if region.kind == "room":
            assert (layout.cells[y0:y1, x0:x1] == region.number).all()
        else:
            assert (layout.cells[y0:y1, x0:x1] < 0).all()
    assert (covered == 1).all(), "regions must tile the grid exactly once"
    removed_edges = {(x + 1.0, y + 0.5) for x, y in layout.removed}
    for link in layout.links:
        assert _touching(rects[link.a], rects[link.b], link.at), link
        if link.kind == "opening":
            assert link.at not in removed_edges, f"an opening crosses removed cell {link}"


def hallway_links_are_a_forest(layout) -> bool:
    """The openings between hallway, segment and open-area regions make no cycle."""
    graph = nx.MultiGraph()
    graph.add_nodes_from(r.number for r in layout.regions if r.kind != "room")
    for link in layout.links:
        kinds = {layout.regions[link.a].kind, layout.regions[link.b].kind}
        if "room" not in kinds:
            graph.add_edge(link.a, link.b)
    return nx.is_forest(nx.Graph(graph)) and graph.number_of_edges() == nx.Graph(graph).number_of_edges()


def hallway_cells_are_a_forest(layout) -> bool:
    """The paper's own view: hallway cells (removed ones solid) joined to their
    4-neighbours make no cycle."""
    rows, cols = layout.cells.shape
    graph = nx.Graph()
    hall = layout.cells == HALL
    for y, x in zip(*np.nonzero(hall)):
        graph.add_node((x, y))
        if x + 1 < cols and hall[y, x + 1]:
            graph.add_edge((x, y), (x + 1, y))
        if y + 1 < rows and hall[y + 1, x]:
            graph.add_edge((x, y), (x, y + 1))
    return nx.is_forest(graph)


def every_region_reachable(layout) -> bool:
    """All regions joined to the first vertical hallway through the links."""
    graph = nx.Graph()
    graph.add_nodes_from(r.number for r in layout.regions)
    graph.add_edges_from((k.a, k.b) for k in layout.links)
    return nx.is_connected(graph)
