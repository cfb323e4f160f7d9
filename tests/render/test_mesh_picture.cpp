// render::write_mesh_picture (what `flexframe check --picture` draws): the PNG is written at the
// size asked for, every item's colour appears in it where the item is (filled quads, dots), the
// labels do not overlap, and bad input or an unwritable file fails with the reason and leaves
// nothing behind. Images land in <build>/test_out/render/ for a person to look at.
#include <gtest/gtest.h>

#include <filesystem>

#include "render/graphics_context.h"
#include "render/mesh_picture.h"
#include "tests/render/render_test_support.h"

namespace ff::render {
namespace {

using test::Image;

// an nx x ny plate of unit quads in z = 0; point (i, j) is j * (nx + 1) + i
MeshPicture plate(int nx, int ny) {
  MeshPicture p;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) p.points.insert(p.points.end(), {double(i), double(j), 0.0});
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      p.quads.insert(p.quads.end(), {a, a + 1, a + nx + 2, a + nx + 1});
    }
  p.width = 800;
  p.height = 600;
  p.title = "plate";
  p.subtitle = "test picture";
  return p;
}

// Pixels whose colour is `c` scaled by the lighting: the same direction in RGB space (cosine
// above 0.9995) and not darker than a quarter of it. The mesh grey, the white background and the
// black text are far from every palette colour in direction.
int pixels_of(const Image& img, const std::array<double, 3>& c) {
  const double cn = std::sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2]);
  int count = 0;
  for (const auto& px : img.rgb) {
    const double p[3] = {px[0] / 255.0, px[1] / 255.0, px[2] / 255.0};
    const double pn = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    if (pn < 0.25 * cn) continue;
    const double cosine = (p[0] * c[0] + p[1] * c[1] + p[2] * c[2]) / (pn * cn);
    count += cosine > 0.9995;
  }
  return count;
}

// Pixels of the mesh's grey, lit: grey (channels within 14 of each other), neither the white
// background nor dark text.
int mesh_pixels(const Image& img) {
  int count = 0;
  for (const auto& px : img.rgb) {
    const int lo = std::min({px[0], px[1], px[2]}), hi = std::max({px[0], px[1], px[2]});
    count += lo >= 90 && hi <= 235 && hi - lo <= 14;
  }
  return count;
}

class MeshPictureTest : public ::testing::Test {
 protected:
  void SetUp() override {
    std::string error;
    gc_ = GraphicsContext::create(&error);
    ASSERT_NE(gc_, nullptr) << error;
  }
  std::unique_ptr<GraphicsContext> gc_;
};

TEST_F(MeshPictureTest, WritesThePictureAtItsSizeWithEveryItemsColour) {
  MeshPicture p = plate(8, 4);
  PictureItem surface;  // the left half, filled
  surface.color = picture_color(0, 0.3);
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i) surface.quads.push_back(j * 8 + i);
  surface.anchor = 2 * 9 + 2;
  surface.label = surface.legend = "group 'left' (surface)";
  PictureItem edge;  // the right edge x = 8, as dots and a line
  edge.color = picture_color(3);
  for (int j = 0; j <= 4; ++j) edge.nodes.push_back(j * 9 + 8);
  edge.anchor = 2 * 9 + 8;
  edge.label = edge.legend = "bc[0] clamped (5 nodes)";
  PictureItem probe;  // one node on that edge, shared: drawn smaller over it
  probe.color = picture_color(4);
  probe.nodes = {4 * 9 + 8};
  probe.anchor = 4 * 9 + 8;
  probe.label = probe.legend = "probe[0] tip (node 44)";
  p.items = {surface, edge, probe};

  const std::string path = test::out_dir() + "/mesh_picture_plate.png";
  std::filesystem::remove(path);
  std::string error;
  ASSERT_TRUE(write_mesh_picture(*gc_, p, path, &error)) << error;
  const Image img = test::read_png(path);
  ASSERT_EQ(img.width, 800);
  ASSERT_EQ(img.height, 600);
  // the filled half is a large area; the dots and line of the edge and the probe's dot are small
  EXPECT_GT(pixels_of(img, surface.color), 5000);
  EXPECT_GT(pixels_of(img, edge.color), 150);
  EXPECT_GT(pixels_of(img, probe.color), 10);
  EXPECT_GT(mesh_pixels(img), 5000);  // the right half: no item fills it

  // without the items none of their colours is there (the counts above are not the mesh's)
  MeshPicture bare = plate(8, 4);
  const std::string bare_path = test::out_dir() + "/mesh_picture_bare.png";
  ASSERT_TRUE(write_mesh_picture(*gc_, bare, bare_path, &error)) << error;
  const Image none = test::read_png(bare_path);
  EXPECT_EQ(pixels_of(none, surface.color), 0);
  EXPECT_EQ(pixels_of(none, edge.color), 0);
  EXPECT_EQ(pixels_of(none, probe.color), 0);
}

// A plate in the plane x = -y is seen edge-on from (1, -1, 1): the view turns to another of
// (±1, ±1, 1), from which its face shows.
TEST_F(MeshPictureTest, APlateSeenEdgeOnIsViewedFromAnotherSide) {
  MeshPicture p = plate(8, 4);
  for (std::size_t i = 0; i < p.points.size(); i += 3) {
    const double x = p.points[i], y = p.points[i + 1];
    p.points[i] = x / std::sqrt(2.0);
    p.points[i + 1] = -x / std::sqrt(2.0);
    p.points[i + 2] = y;
  }
  const std::string path = test::out_dir() + "/mesh_picture_edge_on.png";
  std::string error;
  ASSERT_TRUE(write_mesh_picture(*gc_, p, path, &error)) << error;
  const Image img = test::read_png(path);
  // the 8 x 4 plate fills much of the picture (from (1, -1, 1) it was a line of some 2000 pixels)
  EXPECT_GT(mesh_pixels(img), 40000);
}

TEST_F(MeshPictureTest, SameInputGivesTheSameBytes) {
  MeshPicture p = plate(3, 3);
  PictureItem corner;
  corner.color = picture_color(1);
  corner.nodes = {0};
  corner.anchor = 0;
  corner.label = corner.legend = "load[0] force (1 node)";
  p.items = {corner};
  const std::string a = test::out_dir() + "/mesh_picture_a.png", b = test::out_dir() + "/mesh_picture_b.png";
  std::string error;
  ASSERT_TRUE(write_mesh_picture(*gc_, p, a, &error)) << error;
  ASSERT_TRUE(write_mesh_picture(*gc_, p, b, &error)) << error;
  EXPECT_EQ(test::file_bytes(a), test::file_bytes(b));
}

TEST_F(MeshPictureTest, BadInputFailsWithTheReasonAndWritesNothing) {
  const std::string path = test::out_dir() + "/mesh_picture_bad.png";
  std::filesystem::remove(path);
  std::string error;
  MeshPicture p = plate(2, 2);
  p.quads[5] = 99;
  EXPECT_FALSE(write_mesh_picture(*gc_, p, path, &error));
  EXPECT_NE(error.find("point 99"), std::string::npos) << error;
  p = plate(2, 2);
  PictureItem item;
  item.legend = "bc[0]";
  item.nodes = {-1};
  p.items = {item};
  EXPECT_FALSE(write_mesh_picture(*gc_, p, path, &error));
  EXPECT_NE(error.find("bc[0]"), std::string::npos) << error;
  p = plate(2, 2);
  p.points[4] = std::nan("");
  EXPECT_FALSE(write_mesh_picture(*gc_, p, path, &error));
  EXPECT_NE(error.find("not finite"), std::string::npos) << error;
  EXPECT_FALSE(std::filesystem::exists(path));

  // a folder that does not exist: the reason names the file
  const std::string missing = test::out_dir() + "/no_such_folder/picture.png";
  EXPECT_FALSE(write_mesh_picture(*gc_, plate(2, 2), missing, &error));
  EXPECT_NE(error.find(missing), std::string::npos) << error;
  EXPECT_FALSE(std::filesystem::exists(test::out_dir() + "/no_such_folder"));
}

TEST(PlaceLabels, BoxesAroundOneCrowdedPointDoNotOverlapAndStayInTheArea) {
  // six labels on one point (several selections of one node) and two near it
  std::vector<std::array<double, 2>> anchors(6, {400.0, 300.0}), sizes(8, {180.0, 24.0});
  anchors.push_back({420.0, 310.0});
  anchors.push_back({380.0, 290.0});
  const PixelBox area{10, 10, 790, 590};
  const std::vector<PixelBox> occupied = {{10, 540, 300, 590}};  // a title
  const std::vector<PixelBox> boxes = place_labels(anchors, sizes, {300.0, 300.0}, area, occupied);
  ASSERT_EQ(boxes.size(), anchors.size());
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    const PixelBox& b = boxes[i];
    EXPECT_NEAR(b.x1 - b.x0, 180.0, 1e-9);
    EXPECT_NEAR(b.y1 - b.y0, 24.0, 1e-9);
    EXPECT_TRUE(b.x0 >= area.x0 && b.y0 >= area.y0 && b.x1 <= area.x1 && b.y1 <= area.y1)
        << "box " << i << ": " << b.x0 << " " << b.y0 << " " << b.x1 << " " << b.y1;
    EXPECT_FALSE(b.overlaps(occupied[0])) << "box " << i;
    for (std::size_t j = 0; j < i; ++j) { EXPECT_FALSE(b.overlaps(boxes[j])) << "boxes " << j << " and " << i; }
    for (const auto& a : anchors)  // no box hides a labelled point
      EXPECT_FALSE(a[0] > b.x0 && a[0] < b.x1 && a[1] > b.y0 && a[1] < b.y1) << "box " << i;
  }
  // the first label goes to the side away from the centre of the picture (the anchor is right of it)
  EXPECT_GT(boxes[0].x0, 400.0);
}

}  // namespace
}  // namespace ff::render
