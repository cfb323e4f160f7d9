// Writes the STEP files of this folder (README.md): a 1000 x 500 panel in the plane z = 0 with a
// blade stiffener 60 high along x at y = 250, the blade's foot lying on the panel without sharing
// an edge with it, as CAD exports often are. Built with Gmsh's OpenCASCADE kernel, never fused or
// fragmented; each file was written once:
//   g++ make_stiffened_panels.cpp -o make_stiffened_panels -lgmsh && ./make_stiffened_panels
#include <gmsh.h>

#include <string>

namespace occ = gmsh::model::occ;

namespace {

// the blade: a face in the plane y = 250 from z = 0 (its foot) to z = 60
void add_blade() {
  const int p1 = occ::addPoint(0, 250, 0), p2 = occ::addPoint(1000, 250, 0), p3 = occ::addPoint(1000, 250, 60),
            p4 = occ::addPoint(0, 250, 60);
  const int loop = occ::addCurveLoop({occ::addLine(p1, p2), occ::addLine(p2, p3), occ::addLine(p3, p4), occ::addLine(p4, p1)});
  occ::addPlaneSurface({loop});
}

void write(const std::string& name, bool panel_in_two_faces) {
  gmsh::model::add(name);
  if (panel_in_two_faces) {  // split at x = 400, each face with its own edge there
    occ::addRectangle(0, 0, 0, 400, 500);
    occ::addRectangle(400, 0, 0, 600, 500);
  } else {
    occ::addRectangle(0, 0, 0, 1000, 500);
  }
  add_blade();
  occ::synchronize();
  gmsh::write(name + ".step");
  gmsh::model::remove();
}

}  // namespace

int main() {
  gmsh::initialize();
  write("stiffened_panel_one_face", false);
  write("stiffened_panel_two_faces", true);
  gmsh::finalize();
  return 0;
}
