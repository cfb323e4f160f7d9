#include "render/mesh_export.h"

#include <vtkCellArray.h>
#include <vtkCellType.h>
#include <vtkDoubleArray.h>
#include <vtkFieldData.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkStringArray.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>
#include <vtkXMLUnstructuredGridWriter.h>

#include <cstdio>
#include <cerrno>
#include <cstring>
#include <mutex>

#include "core/frame/output_file.h"
#include "render/graphics_context.h"
#include "render/vtk_messages.h"

namespace ff::render {
namespace {

vtkNew<vtkDoubleArray> one_value(const char* name, double v) {
  vtkNew<vtkDoubleArray> a;
  a->SetName(name);
  a->SetNumberOfTuples(1);
  a->SetValue(0, v);
  return a;
}

// `bytes` as the whole of the file `path`, opened without following a link (core/frame/output_file.h);
// "" or why not ("disk full (...)" for ENOSPC and EDQUOT)
std::string write_whole_file(const std::string& path, const std::string& bytes) {
  const auto reason = [](int e) {
    return std::string(e == ENOSPC || e == EDQUOT ? "disk full (" : "write failed (") + std::strerror(e) + ")";
  };
  std::string why;
  std::FILE* f = open_output_stream(path, &why);
  if (!f) return errno != 0 ? reason(errno) : why;
  const bool written = std::fwrite(bytes.data(), 1, bytes.size(), f) == bytes.size();
  int e = written ? 0 : errno;
  if (std::fclose(f) != 0 && e == 0) e = errno;
  if (written && e == 0) return "";
  std::remove(path.c_str());  // the file this call made, never a link (refused above)
  return reason(e != 0 ? e : EIO);
}

// minimal XML escaping for attribute values
std::string xml_attr(const std::string& s) {
  std::string out;
  for (char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace

bool write_vtu(const std::string& path, const RunInfo& info, const Frame& frame, std::string* error,
               const VtuExtras& extras) {
  auto fail = [&](const std::string& why) {
    if (error) *error = "'" + path + "': " + why;
    return false;
  };
  const FrameMesh& mesh = info.mesh;
  const std::size_t n = mesh.point_count();
  if (frame.points.size() != 3 * n)
    return fail("frame has " + std::to_string(frame.points.size()) + " point coordinates, the mesh needs " +
                std::to_string(3 * n));
  const bool have_base = !frame.base_points.empty();
  if (have_base && frame.base_points.size() != 3 * n) return fail("frame base_points do not match the mesh");
  if (frame.fields.size() != info.fields.size()) return fail("frame fields do not match the run's field list");
  for (const auto& f : frame.fields)
    if (f.size() != n) return fail("a frame field does not have one value per point");
  for (const auto& [name, values] : extras.point_vectors)
    if (values.size() != 3 * n) return fail("point vectors '" + name + "' do not have 3 values per point");
  for (const auto* cells : {&mesh.lines, &mesh.triangles, &mesh.quads})
    for (std::int32_t v : *cells)
      if (v < 0 || static_cast<std::size_t>(v) >= n) return fail("a mesh cell refers to a point that does not exist");

  install_vtk_message_filter();
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  vtkNew<vtkUnstructuredGrid> grid;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) points->SetPoint(static_cast<vtkIdType>(i), &frame.points[3 * i]);
  grid->SetPoints(points);

  const std::size_t cell_count = mesh.lines.size() / 2 + mesh.triangles.size() / 3 + mesh.quads.size() / 4;
  grid->Allocate(static_cast<vtkIdType>(cell_count));
  auto add_cells = [&](const std::vector<std::int32_t>& c, std::size_t per, int type) {
    vtkIdType ids[4];
    for (std::size_t e = 0; e + per <= c.size(); e += per) {
      for (std::size_t k = 0; k < per; ++k) ids[k] = c[e + k];
      grid->InsertNextCell(type, static_cast<vtkIdType>(per), ids);
    }
  };
  add_cells(mesh.lines, 2, VTK_LINE);
  add_cells(mesh.triangles, 3, VTK_TRIANGLE);
  add_cells(mesh.quads, 4, VTK_QUAD);

  vtkPointData* pd = grid->GetPointData();
  for (std::size_t k = 0; k < info.fields.size(); ++k) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(info.fields[k].name.c_str());
    a->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t i = 0; i < n; ++i) a->SetValue(static_cast<vtkIdType>(i), frame.fields[k][i]);
    pd->AddArray(a);
  }
  auto add_vector = [&](const char* name, const std::vector<double>& from) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name);
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t i = 0; i < 3 * n; ++i) a->SetValue(static_cast<vtkIdType>(i), frame.points[i] - from[i]);
    pd->AddArray(a);
  };
  add_vector("displacement_xyz", mesh.reference_points);
  if (have_base) add_vector("elastic_displacement_xyz", frame.base_points);
  for (const auto& [name, values] : extras.point_vectors) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfComponents(3);
    a->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t i = 0; i < 3 * n; ++i) a->SetValue(static_cast<vtkIdType>(i), values[i]);
    pd->AddArray(a);
  }
  if (!info.fields.empty()) pd->SetActiveScalars(info.fields.front().name.c_str());

  vtkFieldData* fd = grid->GetFieldData();
  fd->AddArray(one_value("TimeValue", frame.time));
  fd->AddArray(one_value("step", static_cast<double>(frame.step)));
  fd->AddArray(one_value("load_factor", frame.load_factor));
  vtkNew<vtkStringArray> units;
  units->SetName("field_units");
  for (const Quantity& q : info.fields) {
    std::string s = q.name + ": " + (q.label.empty() ? q.name : q.label);
    if (!q.unit.empty()) s += " [" + q.unit + "]";
    units->InsertNextValue(s);
  }
  fd->AddArray(units);
  for (const auto& [name, values] : extras.field_arrays) {
    vtkNew<vtkDoubleArray> a;
    a->SetName(name.c_str());
    a->SetNumberOfTuples(static_cast<vtkIdType>(values.size()));
    for (std::size_t i = 0; i < values.size(); ++i) a->SetValue(static_cast<vtkIdType>(i), values[i]);
    fd->AddArray(a);
  }

  MessageCapture vtk_errors;
  // VTK writes into a string and the file is ours to open: VTK's own open would follow a link
  vtkNew<vtkXMLUnstructuredGridWriter> writer;
  writer->WriteToOutputStringOn();
  writer->SetInputData(grid);
  writer->SetDataModeToAppended();
  writer->SetCompressorTypeToZLib();
  if (writer->Write() != 1 || writer->GetErrorCode() != 0)
    return fail("could not write the VTU file" + (vtk_errors.empty() ? std::string() : ": " + vtk_errors.text()));
  if (const std::string why = write_whole_file(path, writer->GetOutputString()); !why.empty())
    return fail("could not write the VTU file: " + why);
  return true;
}

bool write_pvd(const std::string& path, const std::vector<PvdEntry>& entries, std::string* error) {
  std::string out = "<?xml version=\"1.0\"?>\n"
                    "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
  for (const PvdEntry& e : entries) {
    char t[40];
    std::snprintf(t, sizeof t, "%.17g", e.time);
    out += std::string("    <DataSet timestep=\"") + t + "\" group=\"\" part=\"0\" file=\"" + xml_attr(e.file) + "\"/>\n";
  }
  out += "  </Collection>\n</VTKFile>\n";
  if (const std::string why = write_whole_file(path, out); !why.empty()) {
    if (error) *error = "'" + path + "': " + why;
    return false;
  }
  return true;
}

}  // namespace ff::render
