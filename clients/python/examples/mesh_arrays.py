"""(V, F) numpy arrays from an OFF or OBJ file, for the examples (trimesh, libigl or
potpourri3d users already have their arrays and skip this)."""
import numpy as np


def load(path):
    """Vertices (n, 3) float64 and triangles (m, 3) int64; polygons are fanned like the server does."""
    text = open(path).read()
    if path.lower().endswith(".off"):
        tok = text.split()
        start = 1 if tok[0] == "OFF" else 0
        nv, nf = int(tok[start]), int(tok[start + 1])
        i = start + 3
        V = np.array(tok[i:i + 3 * nv], dtype=np.float64).reshape(nv, 3)
        i += 3 * nv
        polys = []
        for _ in range(nf):
            k = int(tok[i])
            polys.append([int(v) for v in tok[i + 1:i + 1 + k]])
            i += 1 + k
    elif path.lower().endswith(".obj"):
        verts, polys = [], []
        for line in text.splitlines():
            p = line.split()
            if p and p[0] == "v":
                verts.append([float(x) for x in p[1:4]])
            elif p and p[0] == "f":
                ids = [int(x.split("/")[0]) for x in p[1:]]
                polys.append([x - 1 if x > 0 else len(verts) + x for x in ids])
        V = np.array(verts, dtype=np.float64)
    else:
        raise SystemExit("this loader reads .off and .obj; pass other formats to Client.run as a file path")
    F = np.array([(p[0], p[j], p[j + 1]) for p in polys for j in range(1, len(p) - 1)], dtype=np.int64)
    return V, F
