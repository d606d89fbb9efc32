"""Writes the fixtures two_hexes_41.msh (Gmsh 4.1 ASCII), two_hexes_41_binary.msh (4.1
binary), two_hexes_22.msh (2.2 ASCII) and tet_triangles.inp (Abaqus, as meshio writes a
tetrahedron with triangles) with meshio 5.3.5, independently of musclefem's readers:

    python -m venv venv && venv/bin/pip install meshio==5.3.5
    venv/bin/python write_gmsh_versions.py

Two unit hexes side by side along x (physical volume "muscle", tag 1) and the two quads of
their top face z = 1 (physical surface "top", tag 2). Node tags start at 1; the 4.1 files
list the top face's nodes first (one block per entity).
"""

import meshio
import numpy as np

points = np.array(
    [[i, j, k] for k in (0.0, 1.0) for j in (0.0, 1.0) for i in (0.0, 1.0, 2.0)]
)
# Node index i + 3j + 6k; hexes in Gmsh's (= Abaqus's) order.
hexes = np.array([[0, 1, 4, 3, 6, 7, 10, 9], [1, 2, 5, 4, 7, 8, 11, 10]])
# The top faces, counter-clockwise seen from +z (outward).
quads = np.array([[6, 7, 10, 9], [7, 8, 11, 10]])
mesh = meshio.Mesh(
    points,
    [("hexahedron", hexes), ("quad", quads)],
    cell_data={
        "gmsh:physical": [np.array([1, 1]), np.array([2, 2])],
        "gmsh:geometrical": [np.array([1, 1]), np.array([1, 1])],
    },
    field_data={"muscle": np.array([1, 3]), "top": np.array([2, 2])},
    # Nodes of the top face on surface entity 1, the others in volume entity 1.
    point_data={
        "gmsh:dim_tags": np.array([[2, 1] if p[2] == 1.0 else [3, 1] for p in points])
    },
)
meshio.write("two_hexes_41.msh", mesh, file_format="gmsh", binary=False)
meshio.write("two_hexes_41_binary.msh", mesh, file_format="gmsh", binary=True)
meshio.write("two_hexes_22.msh", mesh, file_format="gmsh22", binary=False)

tet = meshio.Mesh(
    np.array([[0.0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]]),
    [("tetra", np.array([[0, 1, 2, 3]])), ("triangle", np.array([[0, 2, 1], [1, 2, 3]]))],
)
meshio.write("tet_triangles.inp", tet)
