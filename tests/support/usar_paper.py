"""The UvA paper's room catalogue, typed from the paper for tests (independent of the
shipped CSV)."""

# Zwennes 2011, Appendix A: name, size (columns x rows), difficulty
PAPER = [
    ("dark", 1, 1, 0.5), ("empty", 1, 1, 0.5), ("bisquare", 2, 2, 1.5), ("maze", 2, 2, 2.5),
    ("Maze (smaller)", 2, 2, 4.0), ("Boiler Room", 1, 1, 6.8), ("Dragon Room", 2, 2, 5.5),
    ("Warehouse", 2, 2, 4.0), ("Futuristic Reception", 2, 2, 3.5), ("Water Room", 3, 3, 9.0),
    ("Maze2", 6, 6, 9.5), ("Computer Lab", 2, 2, 5.0), ("Single Office", 1, 1, 5.25),
    ("Multi Office", 2, 1, 5.75), ("CompLab unlit destroyed", 2, 2, 7.3),
    ("Cubicle unlit", 4, 4, 6.25), ("Cubicle unlit destroyed", 4, 4, 8.0),
    ("Single office north destroyed", 1, 1, 7.0), ("MultiOffice tight unlit dest", 2, 1, 7.2),
    ("victims", 1, 2, 2.0),
]
