// The Abaqus .inp reader (app/io/abaqus_inp.h): the sample deck reads to the generator's plate,
// labels in any order map to file-order indices, sets (labels, GENERATE, names of sets, repeats)
// become groups, triangles and entities are kept, keywords are case-insensitive, every refusal
// names the file, the line and the reason, and no truncated or mutated deck crashes the reader.
// Scratch files go to ${FF_BINARY_DIR}/test_out/abaqus_inp/.
#include <gtest/gtest.h>

#include "tests/support/scratch_files.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "app/io/abaqus_inp.h"
#include "core/mesh/generators.h"

using namespace ff::mesh;
namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) { return ff::testing::scratch_path("abaqus_inp", name); }

std::string write_text(const std::string& name, const std::string& text) {
  return ff::testing::write_scratch("abaqus_inp", name, text);
}

const ImportedGroup* group(const ImportedSurface& s, const std::string& name, int dimension) {
  for (const ImportedGroup& g : s.groups)
    if (g.name == name && g.dimension == dimension) return &g;
  return nullptr;
}

// reads `text` as a deck; on failure *error holds the message
bool read_text(const std::string& name, const std::string& text, ImportedSurface& out, std::string* error,
               double limit = 0) {
  return ff::io::read_abaqus_inp(write_text(name, text), out, error, limit);
}

const std::string kTwoQuads =
    "*HEADING\n"
    "two quads\n"
    "*NODE\n"
    "10, 0, 0, 0\n"
    "20, 1, 0, 0\n"
    "30, 2, 0, 0\n"
    "11, 0, 1, 0\n"
    "21, 1, 1, 0\n"
    "31, 2, 1, 0\n"
    "*ELEMENT, TYPE=S4R, ELSET=PLATE\n"
    "7, 10, 20, 21, 11\n"
    "3, 20, 30, 31, 21\n";

}  // namespace

TEST(AbaqusInp, SampleDeckIsTheGeneratorPlate) {
  const std::string path = std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_s4r.inp";
  ImportedSurface s;
  std::string error;
  ASSERT_TRUE(ff::io::read_abaqus_inp(path, s, &error)) << error;
  const ShellMesh plate = rectangular_plate(1, 1, 8, 8);
  EXPECT_EQ(s.format, "Abaqus INP");
  EXPECT_EQ(s.file, path);
  ASSERT_EQ(s.points.size(), plate.points.size());
  for (std::size_t i = 0; i < s.points.size(); ++i) { EXPECT_LT((s.points[i] - plate.points[i]).norm(), 1e-15) << i; }
  ASSERT_EQ(s.elements.size(), plate.quads.size());
  for (std::size_t q = 0; q < s.elements.size(); ++q) {
    EXPECT_EQ(s.elements[q].nodes, plate.quads[q]) << q;
    EXPECT_EQ(s.elements[q].entity, 1);
  }
  EXPECT_EQ(s.elements[63].where, "element 64 (line " + std::to_string(6 + 81 + 1 + 64) + ")");
  ASSERT_EQ(s.groups.size(), 3u);
  const ImportedGroup* clamped = group(s, "CLAMPED", 0);
  const ImportedGroup* loaded = group(s, "LOADED", 0);
  const ImportedGroup* all = group(s, "PLATE", 2);
  ASSERT_TRUE(clamped && loaded && all);
  ASSERT_EQ(clamped->nodes.size(), 9u);
  ASSERT_EQ(loaded->nodes.size(), 9u);
  for (int p : clamped->nodes) { EXPECT_EQ(s.points[p].x(), 0.0); }
  for (int p : loaded->nodes) { EXPECT_EQ(s.points[p].x(), 1.0); }
  EXPECT_TRUE(clamped->elements.empty() && clamped->segments.empty());
  EXPECT_EQ(all->elements.size(), 64u);
  EXPECT_TRUE(all->nodes.empty());
  EXPECT_EQ(clamped->origin, "*NSET at line " + std::to_string(6 + 81 + 1 + 64 + 1));
  ASSERT_EQ(s.notes.size(), 1u);
  EXPECT_NE(s.notes[0].find("81 nodes, 64 quads"), std::string::npos) << s.notes[0];
}

TEST(AbaqusInp, LabelsMapToFileOrderAndSetsBecomeGroups) {
  const std::string deck =
      "** elements before the nodes they name, labels in no order\n"
      "*ELEMENT, TYPE=S4, ELSET=LEFT\n"
      "900, 5, 1001, 44, 7\n"
      "*ELEMENT, TYPE=S4R5, ELSET=RIGHT\n"
      "12, 1001, 3, 8, 44\n"
      "*NODE, NSET=ALL\n"
      "5, 0., 0., 0.\n"
      "1001, 1., 0., 0.\n"
      "3, 2., 0., 0.\n"
      "7, 0., 1., 0.\n"
      "44, 1., 1., 0.\n"
      "8, 2., 1., 0.\n"
      "*NSET, NSET=BOTTOM\n"
      "5, 1001, 3, 5\n"
      "*NSET, NSET=ODD, GENERATE\n"
      "3, 7, 2\n"
      "*NSET, NSET=BOTTOM\n"
      "ODD, 44\n"
      "*ELSET, ELSET=BOTH\n"
      "LEFT, 12,\n"
      "900\n"
      "*ELSET, ELSET=RANGE, GENERATE\n"
      "12, 12\n";
  ImportedSurface s;
  std::string error;
  ASSERT_TRUE(read_text("labels.inp", deck, s, &error)) << error;
  ASSERT_EQ(s.points.size(), 6u);
  EXPECT_EQ(s.points[1], Eigen::Vector3d(1, 0, 0));  // label 1001 is the second node written
  ASSERT_EQ(s.elements.size(), 2u);
  EXPECT_EQ(s.elements[0].nodes, (std::array<int, 4>{0, 1, 4, 3}));
  EXPECT_EQ(s.elements[1].nodes, (std::array<int, 4>{1, 2, 5, 4}));
  EXPECT_EQ(s.elements[0].entity, 1);
  EXPECT_EQ(s.elements[1].entity, 2);
  EXPECT_EQ(s.elements[0].where, "element 900 (line 3)");
  EXPECT_EQ(s.elements[1].where, "element 12 (line 5)");
  // BOTTOM: its first block (5 repeated kept once), then the second block adds ODD's nodes and 44
  const ImportedGroup* bottom = group(s, "BOTTOM", 0);
  ASSERT_TRUE(bottom);
  EXPECT_EQ(bottom->nodes, (std::vector<int>{0, 1, 2, 3, 4}));
  EXPECT_EQ(group(s, "ODD", 0)->nodes, (std::vector<int>{2, 0, 3}));  // labels 3, 5, 7
  EXPECT_EQ(group(s, "ALL", 0)->nodes, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(group(s, "LEFT", 2)->elements, (std::vector<int>{0}));
  EXPECT_EQ(group(s, "RIGHT", 2)->elements, (std::vector<int>{1}));
  EXPECT_EQ(group(s, "BOTH", 2)->elements, (std::vector<int>{0, 1}));
  EXPECT_EQ(group(s, "RANGE", 2)->elements, (std::vector<int>{1}));
  EXPECT_EQ(group(s, "ALL", 0)->origin, "*NODE NSET= at line 6");
  EXPECT_EQ(group(s, "LEFT", 2)->origin, "*ELEMENT ELSET= at line 2");
  EXPECT_EQ(s.groups.size(), 7u);
}

TEST(AbaqusInp, TrianglesAndQuadsTogether) {
  const std::string deck =
      "*NODE\n"
      "1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 2, 0, 0\n"
      "*ELEMENT, TYPE=S4R\n"
      "1, 1, 2, 3, 4\n"
      "*ELEMENT, TYPE=S3, ELSET=TRI\n"
      "2, 2, 5, 3\n"
      "*ELEMENT, TYPE=S3R, ELSET=TRI\n"
      "3, 5, 2, 3\n";
  ImportedSurface s;
  std::string error;
  ASSERT_TRUE(read_text("triangles.inp", deck, s, &error)) << error;
  ASSERT_EQ(s.elements.size(), 3u);
  EXPECT_FALSE(s.elements[0].triangle());
  EXPECT_TRUE(s.elements[1].triangle());
  EXPECT_EQ(s.elements[1].nodes, (std::array<int, 4>{1, 4, 2, -1}));
  EXPECT_EQ(s.elements[2].nodes, (std::array<int, 4>{4, 1, 2, -1}));
  EXPECT_EQ(s.elements[0].entity, 0);  // no ELSET
  EXPECT_EQ(s.elements[1].entity, 1);
  EXPECT_EQ(s.elements[2].entity, 1);  // the same set, the same entity
  EXPECT_EQ(group(s, "TRI", 2)->elements, (std::vector<int>{1, 2}));
  EXPECT_NE(s.notes[0].find("1 quad (S4/S4R/S4R5), 2 triangles (S3/S3R)"), std::string::npos) << s.notes[0];
}

TEST(AbaqusInp, KeywordsParametersAndNamesAreCaseInsensitive) {
  const std::string deck =
      "\xEF\xBB\xBF*Heading\r\n"
      "** a byte order mark, Windows line ends, mixed case, a keyword line continued, Fortran exponents\r\n"
      "*Part, name=Plate\r\n"
      "*node, nset=Edge\r\n"
      "1, 0.0D0, 0., 0.\r\n"
      "2, 1.0d+00, 0., 0.\r\n"
      "*Node\r\n"
      "  3 , +1.0E0 , 1.0 , 0.0\r\n"
      "4, .0, 1., -0.\r\n"
      "*Element, type=s4r,\r\n"
      "  Elset=Shell\r\n"
      "1, 1, 2,\r\n"
      "3, 4\r\n"
      "*nset, NSET=edge, Generate\r\n"
      "3, 4\r\n"
      "*ElSet, elset=sHeLL\r\n"
      "1\r\n"
      "*nset, nset=Copy\r\n"
      "EDGE\r\n"
      "*End Part\r\n";
  ImportedSurface s;
  std::string error;
  ASSERT_TRUE(read_text("case.inp", deck, s, &error)) << error;
  ASSERT_EQ(s.points.size(), 4u);
  EXPECT_EQ(s.points[1], Eigen::Vector3d(1, 0, 0));
  EXPECT_EQ(s.points[2], Eigen::Vector3d(1, 1, 0));
  ASSERT_EQ(s.elements.size(), 1u);
  EXPECT_EQ(s.elements[0].nodes, (std::array<int, 4>{0, 1, 2, 3}));
  EXPECT_EQ(s.elements[0].where, "element 1 (line 12)");  // where it starts
  // one set per name whatever its spelling, named as first written
  ASSERT_EQ(s.groups.size(), 3u);
  EXPECT_EQ(group(s, "Edge", 0)->nodes, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(group(s, "Shell", 2)->elements, (std::vector<int>{0}));
  EXPECT_EQ(group(s, "Copy", 0)->nodes, (std::vector<int>{0, 1, 2, 3}));
}

TEST(AbaqusInp, EveryRefusalNamesTheFileLineAndReason) {
  const std::string nodes = "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n";  // lines 1-5
  const std::string quad = "*ELEMENT, TYPE=S4\n1, 1, 2, 3, 4\n";                          // lines 6-7
  struct Case {
    const char* name;
    std::string deck;
    std::string expected;  // after "<path> line "
  };
  const std::string not_read = " is not read: FlexFrame reads nodes, S4/S4R/S3 elements and node/element sets from an "
                               ".inp; write materials, sections, supports and steps in the scene";
  const std::vector<Case> cases = {
      {"material", nodes + quad + "*MATERIAL, NAME=STEEL\n*ELASTIC\n2e11, 0.3\n", "8: *MATERIAL" + not_read},
      {"step", nodes + quad + "*Step\n*Static\n*End Step\n", "8: *STEP" + not_read},
      {"boundary", nodes + quad + "*BOUNDARY\n1, ENCASTRE\n", "8: *BOUNDARY" + not_read},
      {"shell_section", nodes + quad + "*SHELL SECTION, ELSET=A, MATERIAL=M\n0.01\n", "8: *SHELL SECTION" + not_read},
      {"assembly", nodes + quad + "*ASSEMBLY, NAME=A\n", "8: *ASSEMBLY" + not_read},
      {"instance", nodes + quad + "*Instance, name=P-1, part=P\n", "8: *INSTANCE" + not_read},
      {"s8r", nodes + "*ELEMENT, TYPE=S8R\n1, 1, 2, 3, 4, 1, 2, 3, 4\n",
       "6: *ELEMENT TYPE=S8R is not read: FlexFrame reads the shell elements S4, S4R, S4R5 (quads) and S3, S3R"},
      {"c3d8", nodes + "*ELEMENT, TYPE=C3D8\n", "6: *ELEMENT TYPE=C3D8 is not read: FlexFrame reads the shell elements "
                                                 "S4, S4R, S4R5 (quads) and S3, S3R (triangles) from an .inp"},
      {"gmsh_export", "*Heading\n gmsh.inp\n" + nodes + "******* E L E M E N T S *************\n*ELEMENT, type=T3D2, ELSET=Line4\n1, 1, 2\n",
       "9: *ELEMENT TYPE=T3D2 is not read: FlexFrame reads the shell elements S4, S4R, S4R5 (quads) and S3, S3R (triangles) "
       "from an .inp; a deck exported by Gmsh (T3D2 lines, CPS3/CPS4 faces) is read better as its .msh file"},
      {"no_type", nodes + "*ELEMENT, ELSET=A\n", "6: *ELEMENT needs TYPE="},
      {"include", nodes + "*INCLUDE, INPUT=../../etc/passwd\n", "6: *INCLUDE is not read: FlexFrame reads one .inp file"},
      {"unknown_parameter", "*NODE, SYSTEM=C\n1, 0, 0, 0\n", "1: *NODE parameter SYSTEM=C is not read"},
      {"nset_instance", nodes + quad + "*NSET, NSET=A, INSTANCE=P-1\n1\n", "8: *NSET parameter INSTANCE=P-1 is not read"},
      {"undefined_node", nodes + "*ELEMENT, TYPE=S4\n1, 1, 2, 3, 99\n", "7: element 1 names node 99, which no *NODE defines"},
      {"duplicate_node", nodes + "*NODE\n3, 5, 5, 5\n" + quad, "7: node 3 is defined twice (first at line 4)"},
      {"duplicate_element", nodes + quad + "1, 4, 3, 2, 1\n", "8: element 1 is defined twice (first at line 7)"},
      {"set_undefined_node", nodes + quad + "*NSET, NSET=A\n1, 2,\n17\n", "10: set 'A' names node 17, which the file does not define"},
      {"set_undefined_element", nodes + quad + "*ELSET, ELSET=E\n2\n", "9: set 'E' names element 2, which the file does not define"},
      {"set_undefined_set", nodes + quad + "*NSET, NSET=A\nNOPE\n", "9: set 'A' names 'NOPE', which is neither a node label nor a node set"},
      {"set_names_itself", nodes + quad + "*NSET, NSET=A\n1\n*NSET, NSET=A\nA\n", "11: set 'A' names set 'A', which is itself; a set cannot contain itself"},
      {"sets_name_each_other", nodes + quad + "*NSET, NSET=A\nB\n*NSET, NSET=B\nA\n", "11: set 'B' names set 'A', which contains 'B' in turn (directly or through other sets)"},
      {"empty_set", nodes + quad + "*NSET, NSET=A\n*NSET, NSET=B\n1\n", "8: set 'A' is empty"},
      {"empty_set_at_end", nodes + quad + "*ELSET, ELSET=E\n", "8: set 'E' is empty"},
      {"empty_repeat", nodes + quad + "*NSET, NSET=A\n1\n*NSET, NSET=A\n*NSET, NSET=B\n2\n", "10: set 'A' is empty here"},
      {"empty_node_block", nodes + quad + "*NODE, NSET=N\n", "8: set 'N' is empty"},
      {"truncated_node", "*NODE\n1, 0, 0, 0\n2, 1, 0\n", "3: node 2 has 2 coordinates; a node needs its label and three coordinates"},
      {"node_normals", "*NODE\n1, 0, 0, 0, 0, 0, 1\n", "2: node 1: fields after x, y, z (node normals) are not read"},
      {"truncated_element", nodes + "*ELEMENT, TYPE=S4\n1, 1, 2, 3\n", "7: element 1 has 3 of the 4 nodes of an S4 (a truncated line?)"},
      {"element_continued_into_eof", nodes + "*ELEMENT, TYPE=S4R\n1, 1, 2,\n", "7: element 1 has 2 of the 4 nodes of an S4R"},
      {"element_continued_into_keyword", nodes + "*ELEMENT, TYPE=S4R\n1, 1, 2,\n*NSET, NSET=A\n1\n", "7: element 1 has 2 of the 4 nodes"},
      {"too_many_nodes", nodes + "*ELEMENT, TYPE=S3\n1, 1, 2, 3, 4\n", "7: element 1 has more than the 3 nodes of an S3"},
      {"empty_field", "*NODE\n1, , 0, 0\n", "2: field 2 is empty"},
      {"nan", "*NODE\n1, nan, 0, 0\n", "2: node 1: the coordinate nan is not a finite number"},
      {"inf", "*NODE\n1, 0, -inf, 0\n", "2: node 1: the coordinate -inf is not a finite number"},
      {"beyond_1e150", "*NODE\n1, 0, 0, 1e200\n", "2: node 1: the coordinate 1e200 is beyond 1e150"},
      {"beyond_double", "*NODE\n1, 0, 0, 1e999\n", "2: node 1: the coordinate 1e999 is beyond the range of double precision"},
      {"not_a_number", "*NODE\n1, 0, zero, 0\n", "2: node 1: 'zero' is not a number"},
      {"huge_label", "*NODE\n99999999999999999999, 0, 0, 0\n", "2: *NODE: label 99999999999999999999 is not a positive integer below 2^63"},
      {"zero_label", "*NODE\n0, 0, 0, 0\n", "2: *NODE: label 0 is not a positive integer"},
      {"fraction_label", nodes + "*ELEMENT, TYPE=S4\n1, 1.5, 2, 3, 4\n", "7: element 1: '1.5' is not a label"},
      {"generate_step_0", nodes + quad + "*NSET, NSET=A, GENERATE\n1, 4, 0\n", "9: *NSET, GENERATE: the step '0' is not a positive integer"},
      {"generate_reversed", nodes + quad + "*ELSET, ELSET=A, GENERATE\n4, 1\n", "9: *ELSET, GENERATE: the range ends (1) before it starts (4)"},
      {"generate_one_field", nodes + quad + "*NSET, NSET=A, GENERATE\n4\n", "9: *NSET, GENERATE: a line is 'first, last' or 'first, last, step'"},
      {"generate_huge_range", nodes + quad + "*NSET, NSET=A, GENERATE\n1, 9223372036854775807\n",
       "9: set 'A': GENERATE 1, 9223372036854775807, 1 names node 5, which the file does not define"},
      {"generate_value", nodes + quad + "*NSET, NSET=A, GENERATE=YES\n1, 2\n", "8: *NSET: GENERATE takes no value"},
      {"nset_without_name", nodes + quad + "*NSET\n1\n", "8: *NSET needs NSET="},
      {"nset_empty_name", nodes + quad + "*NSET, NSET=\n1\n", "8: *NSET: NSET= needs a name"},
      {"data_first", "1, 0, 0, 0\n", "1: '1, 0, 0, 0' is data before any keyword"},
      {"node_after_part", "*PART, NAME=A\n" + nodes + quad + "*END PART\n*NODE\n5, 0, 0, 0\n", "10: *NODE after *END PART (line 9): FlexFrame reads a single part"},
      {"second_part_keyword", "*PART, NAME=A\n*END PART\n*PART, NAME=B\n", "3: a second *PART (the first at line 1)"},
      {"part_after_content", nodes + quad + "*PART, NAME=A\n", "8: *PART after nodes, elements or sets outside a part (line 1)"},
      {"part_not_ended", "*PART, NAME=A\n" + nodes + quad, "1: *PART has no *END PART: the file ends inside the part"},
      {"end_part_alone", nodes + quad + "*END PART\n", "8: *END PART without a *PART before it"},
      {"data_after_end_part", "*PART, NAME=A\n" + nodes + quad + "*END PART\n5, 0, 0, 0\n", "10: '5, 0, 0, 0' is data after *END PART"},
      {"keyword_continued_into_eof", nodes + quad + "*NSET, NSET=A,\n", "8: the keyword line ends with a comma, but the file ends"},
      {"bare_star", nodes + quad + "*\n", "8: * is not read"},
  };
  for (const Case& c : cases) {
    ImportedSurface s;
    s.format = "untouched";
    std::string error;
    const std::string path = write_text(std::string(c.name) + ".inp", c.deck);
    EXPECT_FALSE(ff::io::read_abaqus_inp(path, s, &error)) << c.name;
    EXPECT_EQ(error.rfind(path + " line ", 0), 0u) << c.name << ": " << error;
    EXPECT_NE(error.find(path + " line " + c.expected), std::string::npos) << c.name << ": " << error;
    EXPECT_EQ(s.format, "untouched") << c.name;
  }
}

TEST(AbaqusInp, WholeFileRefusalsNameTheFile) {
  ImportedSurface s;
  std::string error;
  const std::string missing = scratch("does_not_exist.inp");
  EXPECT_FALSE(ff::io::read_abaqus_inp(missing, s, &error));
  EXPECT_EQ(error, "cannot open " + missing);

  const std::string no_elements = write_text("no_elements.inp", "*HEADING\nnodes only\n*NODE\n1, 0, 0, 0\n");
  EXPECT_FALSE(ff::io::read_abaqus_inp(no_elements, s, &error));
  EXPECT_EQ(error, no_elements + ": no *ELEMENT of type S4, S4R, S4R5, S3 or S3R; a shell needs elements");

  // 2 * 10^5 GENERATE lines over all 10 nodes: 2 * 10^6 steps, beyond 64 times the 11 items + 10^6
  std::string deck = "*NODE\n";
  for (int i = 1; i <= 10; ++i) deck += std::to_string(i) + ", " + std::to_string(i) + ", 0, 0\n";
  deck += "*ELEMENT, TYPE=S4\n1, 1, 2, 3, 4\n*NSET, NSET=MANY, GENERATE\n";
  for (int i = 0; i < 200000; ++i) deck += "1, 10\n";
  const std::string many = write_text("many_ranges.inp", deck);
  EXPECT_FALSE(ff::io::read_abaqus_inp(many, s, &error));
  EXPECT_EQ(error.rfind(many + ": its sets name 2e+06 nodes and elements", 0), 0u) << error;

  // a chain of 300 sets, each naming the one before, would copy 299 * 10^4 members: the limit,
  // 64 * (10^4 nodes + 1 element) + 10^6 = 1640064 steps, is passed at the 163rd copy (10599
  // steps counted before: the range's 10^4 and one per other entry)
  deck = "*NODE\n";
  for (int i = 1; i <= 10000; ++i) deck += std::to_string(i) + ", " + std::to_string(i) + ", 0, 0\n";
  deck += "*ELEMENT, TYPE=S4\n1, 1, 2, 3, 4\n*NSET, NSET=S0, GENERATE\n1, 10000\n";
  for (int i = 1; i < 300; ++i) deck += "*NSET, NSET=S" + std::to_string(i) + "\nS" + std::to_string(i - 1) + "\n";
  const std::string chain = write_text("chain_of_sets.inp", deck);
  EXPECT_FALSE(ff::io::read_abaqus_inp(chain, s, &error));
  EXPECT_EQ(error.rfind(chain + " line " + std::to_string(10005 + 2 * 163) + ": set 'S163' names set 'S162': the sets up to here", 0), 0u)
      << error;

  EXPECT_FALSE(ff::io::read_abaqus_inp(scratch(""), s, &error));
  EXPECT_EQ(error, scratch("") + " is a directory, not an .inp file");
}

TEST(AbaqusInp, MemoryLimitRefusesBeforeReadingMore) {
  // the sample plate: 81 nodes (250 bytes each) and 64 elements (400 bytes each), 64 set members
  const std::string path = std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_s4r.inp";
  ImportedSurface s;
  std::string error;
  EXPECT_TRUE(ff::io::read_abaqus_inp(path, s, &error, 1e6)) << error;
  EXPECT_FALSE(ff::io::read_abaqus_inp(path, s, &error, 10000.0));
  // the 41st node (line 6 + 41) is the first past 10 kB
  EXPECT_EQ(error.rfind(path + " line 47: reading the 41 nodes, 0 elements and 0 set members up to here would need about ", 0), 0u)
      << error;
  EXPECT_NE(error.find("GB, more than the 1e-05 GB this machine allows"), std::string::npos) << error;
}

// Truncations at every byte, byte mutations, line deletions and duplications, numbers swapped for
// extreme ones and random bytes: the reader returns true, or false with a message naming the file.
TEST(AbaqusInp, FuzzedDecksNeverCrash) {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_s4r.inp", std::ios::binary);
  std::stringstream buffer;
  buffer << in.rdbuf();
  std::string valid = buffer.str() + "*ELSET, ELSET=CORNER\n1, 8\n*NSET, NSET=BOTH\nCLAMPED, LOADED\n" +
                      "*ELEMENT, TYPE=S3, ELSET=TRI\n100, 81, 80, 72\n*ELSET, ELSET=ODD, GENERATE\n1, 64, 2\n";
  const std::string path = scratch("fuzz.inp");
  int accepted = 0, refused = 0;
  const auto check = [&](const std::string& text, const std::string& what) {
    std::ofstream(path, std::ios::binary | std::ios::trunc) << text;
    ImportedSurface s;
    std::string error;
    const auto start = std::chrono::steady_clock::now();
    const bool ok = ff::io::read_abaqus_inp(path, s, &error, 1e9);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    EXPECT_LT(seconds, 2.0) << what;
    if (ok) {
      ++accepted;
      for (const ImportedElement& e : s.elements)
        for (int k = 0; k < (e.triangle() ? 3 : 4); ++k)
          ASSERT_TRUE(e.nodes[k] >= 0 && e.nodes[k] < static_cast<int>(s.points.size())) << what;
      for (const ImportedGroup& g : s.groups) {
        ASSERT_FALSE(g.nodes.empty() && g.elements.empty()) << what;
        for (int p : g.nodes) { ASSERT_TRUE(p >= 0 && p < static_cast<int>(s.points.size())) << what; }
        for (int e : g.elements) { ASSERT_TRUE(e >= 0 && e < static_cast<int>(s.elements.size())) << what; }
      }
    } else {
      ++refused;
      ASSERT_EQ(error.find(path), error.rfind("cannot open ", 0) == 0 ? 12u : 0u) << what << ": " << error;
    }
  };
  {
    ImportedSurface s;
    std::string error;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << valid;
    ASSERT_TRUE(ff::io::read_abaqus_inp(path, s, &error)) << error;
  }
  for (std::size_t n = 0; n < valid.size(); n += 5) check(valid.substr(0, n), "truncated at byte " + std::to_string(n));

  // FF_FUZZ_SEED=<n> and FF_FUZZ_SCALE=<k> (k times the mutants) explore beyond the fixed seed,
  // as in tests/cli/cli_fuzz_test.cpp
  const char* seed = std::getenv("FF_FUZZ_SEED");
  const char* scale = std::getenv("FF_FUZZ_SCALE");
  std::mt19937_64 rng(seed && *seed ? std::strtoull(seed, nullptr, 0) : 32);  // issue 32
  const int mutants = 1500 * (scale && *scale ? std::max(1, std::atoi(scale)) : 1);
  const auto below = [&](std::size_t n) { return n ? static_cast<std::size_t>(rng() % n) : 0; };
  const std::vector<std::string> replacements = {"99999999999999999999", "0", "-1", "nan", "1e999", ",", "", "*",
                                                 "**", "*NSET, NSET=X, GENERATE\n1, 9223372036854775807, 1",
                                                 "*ELSET, ELSET=PLATE", "*NODE", "\n", "\r", "1e150", "D", "\"",
                                                 "*ELEMENT, TYPE=S3,\n", "*INCLUDE, INPUT=x.inp"};
  for (int m = 0; m < mutants; ++m) {
    std::string text = valid;
    std::string what = "mutant " + std::to_string(m);
    const int edits = 1 + static_cast<int>(below(4));
    for (int k = 0; k < edits; ++k) {
      const std::size_t at = below(text.size());
      switch (below(5)) {
        case 0:  // one byte, any value
          text[at] = static_cast<char>(below(256));
          break;
        case 1: {  // a number or token replaced
          const std::size_t end = std::min(text.size(), at + 1 + below(8));
          text.replace(at, end - at, replacements[below(replacements.size())]);
          break;
        }
        case 2: {  // a line deleted
          const std::size_t start = text.rfind('\n', at), end = text.find('\n', at);
          if (start != std::string::npos && end != std::string::npos) text.erase(start, end - start);
          break;
        }
        case 3: {  // a line repeated
          const std::size_t start = text.rfind('\n', at), end = text.find('\n', at);
          if (start != std::string::npos && end != std::string::npos) text.insert(end, text.substr(start, end - start));
          break;
        }
        default:  // random bytes spliced in
          std::string junk(1 + below(40), ' ');
          for (char& c : junk) c = static_cast<char>(below(256));
          text.insert(at, junk);
      }
    }
    check(text, what);
  }
  std::string noise(20000, ' ');
  for (char& c : noise) c = static_cast<char>(below(256));
  check(noise, "random bytes");
  check("", "empty file");
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, 0);
  std::printf("fuzzed decks: %d accepted, %d refused\n", accepted, refused);
}
