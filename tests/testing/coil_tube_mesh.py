"""A thin coil as a closed genus-0 triangle mesh, for the CLI tests (standard library only): a tube of `wire` radius
swept along `turns` turns of a helix of radius 1 and pitch `pitch`, `around` vertices per ring, closed by one apex
vertex at each end. Its conformal map compresses area about e^(-pi * length / wire) (issue 24): a 3-turn coil with
wire 1/20 is ~380 wire radii long, far below what a double holds.
"""
import math


def coil(turns=3.0, wire=0.05, pitch=0.3, around=8, spacing=0.04):
    length = turns * math.hypot(2 * math.pi, pitch)
    rings = max(3, int(length / spacing))
    vertices, faces = [], []

    def frame(t):
        c = (math.cos(t), math.sin(t), pitch * t / (2 * math.pi))
        tangent = (-math.sin(t), math.cos(t), pitch / (2 * math.pi))
        n = math.sqrt(sum(x * x for x in tangent))
        tangent = tuple(x / n for x in tangent)
        normal = (-math.cos(t), -math.sin(t), 0.0)
        binormal = (tangent[1] * normal[2] - tangent[2] * normal[1], tangent[2] * normal[0] - tangent[0] * normal[2],
                    tangent[0] * normal[1] - tangent[1] * normal[0])
        return c, tangent, normal, binormal

    t_end = 2 * math.pi * turns
    for i in range(rings):
        c, _, normal, binormal = frame(t_end * i / (rings - 1))
        for j in range(around):
            a = 2 * math.pi * j / around
            vertices.append(tuple(c[k] + wire * (math.cos(a) * normal[k] + math.sin(a) * binormal[k]) for k in range(3)))
    for end, t in ((0, 0.0), (1, t_end)):  # apexes half a wire radius beyond the end rings
        c, tangent, _, _ = frame(t)
        sign = -1 if end == 0 else 1
        vertices.append(tuple(c[k] + sign * 0.5 * wire * tangent[k] for k in range(3)))
    start_apex, end_apex = len(vertices) - 2, len(vertices) - 1
    for i in range(rings - 1):
        for j in range(around):
            a, b = i * around + j, i * around + (j + 1) % around
            c, d = a + around, b + around
            faces += [(a, b, d), (a, d, c)]
    last = (rings - 1) * around
    for j in range(around):
        faces.append((start_apex, (j + 1) % around, j))
        faces.append((end_apex, last + j, last + (j + 1) % around))
    return vertices, faces


def off_text(vertices, faces):
    lines = ["OFF", "%d %d 0" % (len(vertices), len(faces))]
    lines += ["%.17g %.17g %.17g" % v for v in vertices]
    lines += ["3 %d %d %d" % f for f in faces]
    return "\n".join(lines) + "\n"
