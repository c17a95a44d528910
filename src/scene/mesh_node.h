// Where a mesh file places its meshes: what the mesh library reads (meshio/library.h), the reader process sends
// (mesh_wire.h) and the loader turns into instances or one flattened mesh (docs/scene-format.md, "Meshes").
#pragma once

#include "scene/scene.h"

#include <cstdint>
#include <string>

namespace twinray::scene {

// A node that carries a mesh: the mesh (an index into the file's meshes) placed by the node's world transform,
// p ↦ linear·p + translation, its ancestors' matrices composed from the root down. OBJ, PLY and STL have no
// nodes: their one mesh is placed once, as it stands (the defaults).
struct MeshNode {
    std::uint32_t mesh = 0;
    math::Matrix3<double> linear = math::identity_matrix<double>();
    Vec3 translation{0, 0, 0};
    std::string name;  // the node's name in the file, for messages; empty for a file without nodes

    bool is_identity() const {
        const math::Matrix3<double> identity = math::identity_matrix<double>();
        return linear.row[0] == identity.row[0] && linear.row[1] == identity.row[1] &&
               linear.row[2] == identity.row[2] && translation == Vec3{0, 0, 0};
    }
};

}  // namespace twinray::scene
