"""Closed genus-0 meshes with the defect of real spine segmentations (issue 24): one vertex duplicated at exactly
the same position (its "twin") and the two zero-area faces that the twin makes. Otherwise closed, manifold, genus 0.

Made here, in the test, from a subdivided octahedron pushed onto an ellipsoid, so the tests need no data file:
  ellipsoid_mesh(a, b, c, level)  -> (vertices, faces), outward, closed, genus 0
  split_vertex(vertices, faces, v) -> the same surface with v split into v and a twin at v's position: half of v's
                                      fan moves to the twin, two zero-area faces (v, a, twin), (v, twin, b) close it
  off_bytes(vertices, faces)       -> OFF text
"""
import math


def ellipsoid_mesh(a, b, c, level=3):
    """Octahedron subdivided `level` times (4 children per face), normalised to the unit sphere, then scaled."""
    vertices = [(1, 0, 0), (-1, 0, 0), (0, 1, 0), (0, -1, 0), (0, 0, 1), (0, 0, -1)]
    faces = [(0, 2, 4), (2, 1, 4), (1, 3, 4), (3, 0, 4), (2, 0, 5), (1, 2, 5), (3, 1, 5), (0, 3, 5)]
    vertices = [tuple(float(x) for x in v) for v in vertices]
    for _ in range(level):
        midpoint = {}

        def mid(i, j):
            key = (min(i, j), max(i, j))
            if key not in midpoint:
                p, q = vertices[i], vertices[j]
                m = [(p[k] + q[k]) / 2 for k in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                vertices.append(tuple(x / n for x in m))
                midpoint[key] = len(vertices) - 1
            return midpoint[key]

        finer = []
        for i, j, k in faces:
            ij, jk, ki = mid(i, j), mid(j, k), mid(k, i)
            finer += [(i, ij, ki), (ij, j, jk), (ki, jk, k), (ij, jk, ki)]
        faces = finer
    return [(a * x, b * y, c * z) for x, y, z in vertices], faces


def split_vertex(vertices, faces, v):
    """v's fan, ordered (each face (v, x, y) followed by the one starting at y); its first half moves to a new twin
    vertex at v's exact position, and the slit is closed by the zero-area faces (v, a, twin) and (v, twin, b)."""
    fan = []
    for f, face in enumerate(faces):
        if v in face:
            k = face.index(v)
            fan.append((f, face[(k + 1) % 3], face[(k + 2) % 3]))
    ordered = [fan[0]]
    while len(ordered) < len(fan):
        ordered.append(next(g for g in fan if g[1] == ordered[-1][2]))
    twin = len(vertices)
    vertices = list(vertices) + [vertices[v]]
    faces = [list(f) for f in faces]
    half = len(ordered) // 2
    for f, _, _ in ordered[:half]:
        faces[f] = [twin if i == v else i for i in faces[f]]
    a, b = ordered[0][1], ordered[half - 1][2]
    faces += [[v, a, twin], [v, twin, b]]
    return vertices, [tuple(f) for f in faces]


def off_bytes(vertices, faces):
    lines = ["OFF", "%d %d 0" % (len(vertices), len(faces))]
    lines += ["%r %r %r" % tuple(p) for p in vertices]
    lines += ["3 %d %d %d" % tuple(f) for f in faces]
    return ("\n".join(lines) + "\n").encode()


def zero_area_faces(vertices, faces):
    """Faces with three distinct indices whose corners span no area (exactly)."""
    count = 0
    for i, j, k in faces:
        if len({i, j, k}) < 3:
            continue
        p, q, r = vertices[i], vertices[j], vertices[k]
        u = [q[n] - p[n] for n in range(3)]
        w = [r[n] - p[n] for n in range(3)]
        cross = (u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0])
        if cross == (0.0, 0.0, 0.0):
            count += 1
    return count
