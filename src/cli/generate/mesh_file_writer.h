// `twinray generate --mesh-file`: a generated mesh as a file of the formats users exchange, holding exactly
// the doubles the inline lists would (the scene reads the same vertices either way, docs/scene-format.md
// "Meshes"): OBJ as the shortest text that reads back as each double, binary PLY as the doubles' own bytes.
#pragma once

#include "cli/generate/scene_text_writer.h"

#include <cstdio>
#include <string>
#include <vector>

namespace twinray::cli::generate {

// "obj" and "ply": the values of --mesh-file, also the files' extensions.
const std::vector<std::string>& mesh_file_formats();

// Writes the mesh to `stream` in `format` (one of mesh_file_formats()). Throws std::system_error when a write
// fails (a full disk), at the first failed write.
void write_mesh_file(std::FILE* stream, const std::string& format, const MeshLists& lists, MeshCounts counts);

}  // namespace twinray::cli::generate
