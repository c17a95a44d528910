// Embree as the bench's peer (peers/embree_peer.h): its coherent packets of 4, 8 and 16 rays cover every pixel of
// the image once, tiles cut by its edges included, and find what its single rays find.
#include "peers/embree_peer.h"
#include "scene/sphere_field.h"

#include <gtest/gtest.h>

namespace twinray {
namespace {

// 37 x 27 pixels: no tile of 2 x 2, 4 x 2 or 4 x 4 divides it, so every width meets a ragged edge.
TEST(EmbreePeer, CoherentPacketsOfEveryWidthFindTheHitsOfSingleRays) {
    scene::Scene scene = scene::sphere_field(1000);
    scene.width = 37;
    scene.height = 27;
    peers::EmbreePeer peer(scene, 37);
    const peers::FirstHitRun single = peer.cast_single();
    ASSERT_EQ(single.rays, 37u * 27u);
    ASSERT_GT(single.hits, single.rays / 4) << "the field should fill a good part of the image";
    ASSERT_LT(single.hits, single.rays) << "and leave some background";
    for (int lanes : {4, 8, 16}) {
        const peers::FirstHitRun packets = peer.cast_packets(lanes);
        EXPECT_EQ(packets.rays, single.rays) << lanes << " lanes";
        EXPECT_EQ(packets.hits, single.hits) << lanes << " lanes: hits of packets against single rays";
    }
}

}  // namespace
}  // namespace twinray
