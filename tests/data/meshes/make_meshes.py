#!/usr/bin/env python3
"""Writes the mesh files of tests/mesh_file_test.cpp (run from anywhere; the files are committed)."""
import base64
import os
import struct

here = os.path.dirname(os.path.abspath(__file__))


def write(name, data):
    with open(os.path.join(here, name), "wb") as f:
        f.write(data.encode() if isinstance(data, str) else data)


# The unit cube, OBJ numbering (from 1); each face counter-clockwise seen from outside.
cube_vertices = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (0, 1, 0), (0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)]
cube_quads = [(1, 4, 3, 2), (5, 6, 7, 8), (1, 2, 6, 5), (3, 4, 8, 7), (1, 5, 8, 4), (2, 3, 7, 6)]
cube_triangles = [t for a, b, c, d in cube_quads for t in ((a, b, c), (a, c, d))]

obj_vertices = "".join("v %d %d %d\n" % v for v in cube_vertices)
write("cube.obj", "# the unit cube: two groups, quad faces\n" + obj_vertices + "g bottom\nf 1 4 3 2\ng rest\n"
      + "".join("f %d %d %d %d\n" % q for q in cube_quads[1:]))
write("quad.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3 4\n")
# A dart: its second corner is reflex, so the fan from the first corner would leave the polygon.
write("concave.obj", "v 0 0 0\nv 2 1 0\nv 4 0 0\nv 2 3 0\nf 1 2 3 4\n")
# Per-face normals: each corner of the cube is used with three, so it is split in three; relative indices.
normals = [(0, 0, -1), (0, 0, 2), (0, -1, 0), (0, 1, 0), (-1, 0, 0), (1, 0, 0)]
write("cube_normals.obj", "mtllib cube.mtl\n" + obj_vertices + "".join("vn %d %d %d\n" % n for n in normals)
      + "usemtl red\n" + "".join("f " + " ".join("%d//%d" % (v - 9, f - 6) for v in q) + "\n"
                                 for f, q in enumerate(cube_quads)))
write("out_of_range.obj", "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 9\n")
write("nan_vertex.obj", "v 0 0 0\nv 1 0 0\nv nan 1 0\nf 1 2 3\n")
write("bad_number.obj", "v 0 0 0\nv 1 0 0\nv 1 1x 0\nf 1 2 3\n")

# PLY: a cube of side 0.1 (a coordinate that float and double round differently).
side = 0.1
ply_vertices = [tuple(side * c for c in v) for v in cube_vertices]
ply_header = ("ply\nformat %s 1.0\ncomment written by make_meshes.py\nelement vertex 8\n"
              "property %s x\nproperty %s y\nproperty %s z\nelement face %d\nproperty list uchar int vertex_indices\n"
              "end_header\n")
write("cube_ascii.ply", ply_header % ("ascii", "float", "float", "float", 6)
      + "".join("%r %r %r\n" % v for v in ply_vertices)
      + "".join("4 %d %d %d %d\n" % tuple(i - 1 for i in q) for q in cube_quads))


def binary_ply(endian, mark):
    faces = b"".join(struct.pack(mark + "B3i", 3, *(i - 1 for i in t)) for t in cube_triangles)
    return ((ply_header % (endian, "double", "double", "double", 12)).encode()
            + b"".join(struct.pack(mark + "3d", *v) for v in ply_vertices) + faces)


write("cube_binary.ply", binary_ply("binary_little_endian", "<"))
write("cube_binary_big_endian.ply", binary_ply("binary_big_endian", ">"))
write("truncated_binary.ply", binary_ply("binary_little_endian", "<")[:-7])  # inside the last face
write("points_only.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
      "property float z\nend_header\n0 0 0\n1 0 0\n0 1 0\n")

# STL: the same cube of side 0.1, three vertices per triangle (0.1 rounded to float, as STL stores it).
stl_triangles = [[ply_vertices[i - 1] for i in t] for t in cube_triangles]
write("cube_binary.stl", b"cube written by make_meshes.py".ljust(80, b" ") + struct.pack("<I", 12)
      + b"".join(struct.pack("<12fH", 0, 0, 0, *a, *b, *c, 0) for a, b, c in stl_triangles))
write("cube_ascii.stl", "solid cube\n" + "".join(
    "facet normal 0 0 0\n outer loop\n" + "".join("  vertex %r %r %r\n" % v for v in t) + " endloop\nendfacet\n"
    for t in stl_triangles) + "endsolid cube\n")

# glTF: the unit cube (0-based indices) placed by two nodes under a parent that turns them, as .gltf with its buffer a
# data URI and as .glb (a seed of the mesh file fuzzer, which reads each format by its first bytes).
gltf_buffer = b"".join(struct.pack("<3f", *v) for v in cube_vertices) + b"".join(
    struct.pack("<3H", a - 1, b - 1, c - 1) for a, b, c in cube_triangles)


def gltf_json(uri):
    buffer = '{"byteLength": %d%s}' % (len(gltf_buffer), ', "uri": "%s"' % uri if uri else "")
    return ('{"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": ['
            '{"name": "Pair", "rotation": [0, 0.7071068, 0, 0.7071068], "children": [1, 2]}, '
            '{"name": "Near", "mesh": 0}, {"name": "Far", "mesh": 0, "translation": [2, 0, 0]}], '
            '"meshes": [{"name": "cube", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}], '
            '"buffers": [' + buffer + '], "bufferViews": [{"buffer": 0, "byteLength": 96}, '
            '{"buffer": 0, "byteOffset": 96, "byteLength": 72}], "accessors": ['
            '{"bufferView": 0, "componentType": 5126, "count": 8, "type": "VEC3", "min": [0, 0, 0], "max": [1, 1, 1]}, '
            '{"bufferView": 1, "componentType": 5123, "count": 36, "type": "SCALAR"}]}')


write("cube_nodes.gltf", gltf_json("data:application/octet-stream;base64," + base64.b64encode(gltf_buffer).decode()))
glb_json = gltf_json(None).encode().ljust((len(gltf_json(None)) + 3) // 4 * 4, b" ")
write("cube_nodes.glb", b"glTF" + struct.pack("<II", 2, 12 + 8 + len(glb_json) + 8 + len(gltf_buffer))
      + struct.pack("<I", len(glb_json)) + b"JSON" + glb_json
      + struct.pack("<I", len(gltf_buffer)) + b"BIN\0" + gltf_buffer)
