// What the files of hand-solved cases share (plugin/hand_solved.h): the words a case is written in, and each file's
// list.
#pragma once

#include "plugin/hand_solved.h"
#include "scene/scene.h"

#include <string>
#include <utility>
#include <vector>

namespace twinray::plugin::hand_solved {

using V = scene::Vec3;

// A ray and its expected first hit, or a miss.
HandSolvedRay hit(V origin, V direction, const FirstHit& expected);
HandSolvedRay miss(V origin, V direction);

// Appends the cases of one suite to the list.
class Suite {
public:
    Suite(std::vector<HandSolvedCase>& cases, std::string suite) : cases_(cases), suite_(std::move(suite)) {}
    void add(std::string property, scene::Scene scene, std::vector<HandSolvedRay> rays, std::string own_rule = "") {
        cases_.push_back({suite_, std::move(property), std::move(scene), std::move(rays), std::move(own_rule)});
    }

private:
    std::vector<HandSolvedCase>& cases_;
    std::string suite_;
};

// The scene of a far-away decoy sphere that no ray comes near, then the primitive or mesh under test, which is so
// leaf 1: a tracer that reports leaf 0 by default, or the wrong leaf, fails.
scene::Scene after_a_decoy(scene::Object object);
scene::Scene after_a_decoy(scene::Mesh mesh);

// Each file's cases.
void add_primitive_cases(std::vector<HandSolvedCase>& cases);    // hand_solved_primitives.cpp
void add_csg_cases(std::vector<HandSolvedCase>& cases);          // hand_solved_csg.cpp
void add_mesh_cases(std::vector<HandSolvedCase>& cases);         // hand_solved_meshes.cpp
void add_transformed_cases(std::vector<HandSolvedCase>& cases);  // hand_solved_transformed.cpp

}  // namespace twinray::plugin::hand_solved
