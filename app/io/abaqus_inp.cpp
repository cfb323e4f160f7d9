#include "app/io/abaqus_inp.h"

#include "app/io/machine_memory.h"
#include "core/frame/input_file.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string_view>
#include <unordered_map>
#include <vector>

namespace ff::io {

namespace {

using ff::mesh::ImportedElement;
using ff::mesh::ImportedGroup;
using ff::mesh::ImportedSurface;

constexpr const char* kNotRead =
    "FlexFrame reads nodes, S4/S4R/S3 elements and node/element sets from an .inp; write materials, sections, "
    "supports and steps in the scene";

// Peak bytes per node, element and set member while reading and converting: our records and label
// maps, the ImportedSurface, and the shell mesh made from it (the same allowance per vertex and
// face as the OBJ/PLY import, mesh_import.cpp) and, per set member, its record and group entry.
constexpr double kBytesPerNode = 250.0, kBytesPerElement = 400.0, kBytesPerSetMember = 48.0;

// A set names each node or element usefully once; a deck whose sets would walk (labels, names of
// sets, GENERATE ranges up to the first undefined label, repeats included) more than this many
// times its nodes and elements, plus a margin, is refused rather than walked: 10^5 GENERATE lines
// of 20 bytes, each over 10^5 nodes, would take 10^10 steps.
constexpr double kMostNamesPerItem = 64.0, kNamesMargin = 1e6;

std::string_view trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t')) s.remove_suffix(1);
  return s;
}

std::string upper(std::string_view s) {
  std::string u(s);
  for (char& c : u) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return u;
}

// file text in a message: printable, at most 60 characters
std::string shown(std::string_view s) {
  std::string t;
  for (char c : s.substr(0, 60)) t += std::isprint(static_cast<unsigned char>(c)) ? c : '?';
  if (s.size() > 60) t += "...";
  return t;
}

std::string gigabytes(double bytes) {
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", bytes / 1e9);
  return b;
}

// comma-separated fields, each trimmed; a trailing comma ends the line without an empty field
std::vector<std::string_view> split_fields(std::string_view line) {
  std::vector<std::string_view> fields;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    fields.push_back(trim(line.substr(start, comma == std::string_view::npos ? std::string_view::npos : comma - start)));
    if (comma == std::string_view::npos) break;
    start = comma + 1;
  }
  if (fields.size() > 1 && fields.back().empty()) fields.pop_back();
  return fields;
}

bool ends_with_comma(std::string_view s) {
  s = trim(s);
  return !s.empty() && s.back() == ',';
}

// a node or element label, a positive integer; *why says what is wrong otherwise
bool parse_label(std::string_view t, long long& v, std::string* why) {
  std::string_view d = t;
  if (!d.empty() && d.front() == '+') d.remove_prefix(1);
  const auto r = std::from_chars(d.data(), d.data() + d.size(), v);
  if (d.empty() || r.ptr != d.data() + d.size() || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range)) {
    *why = "'" + shown(t) + "' is not a label (a positive integer)";
    return false;
  }
  if (r.ec == std::errc::result_out_of_range || v <= 0) {
    *why = "label " + shown(t) + " is not a positive integer below 2^63";
    return false;
  }
  return true;
}

// a coordinate: C or Fortran notation (1.5, .5, 1., 1e3, 1.5D+03)
bool parse_coordinate(std::string_view t, double& x, std::string* why) {
  std::string s(t);
  if (!s.empty() && s.front() == '+') s.erase(0, 1);
  for (char& c : s)
    if (c == 'd' || c == 'D') c = 'e';
  const auto r = std::from_chars(s.data(), s.data() + s.size(), x);
  if (s.empty() || r.ptr != s.data() + s.size() || (r.ec != std::errc() && r.ec != std::errc::result_out_of_range)) {
    *why = "'" + shown(t) + "' is not a number";
    return false;
  }
  if (r.ec == std::errc::result_out_of_range) {
    *why = "the coordinate " + shown(t) + " is beyond the range of double precision";
    return false;
  }
  if (!std::isfinite(x)) {
    *why = "the coordinate " + shown(t) + " is not a finite number";
    return false;
  }
  if (std::abs(x) > 1e150) {
    *why = "the coordinate " + shown(t) + " is beyond 1e150; lengths must stay far from overflow";
    return false;
  }
  return true;
}

struct Keyword {
  std::string name;  // upper case, inner blanks as one space: "END PART"
  struct Parameter {
    std::string name;   // upper case
    std::string value;  // as written, quotes removed; empty when the parameter has no '='
    bool has_value = false;
  };
  std::vector<Parameter> parameters;
};

Keyword parse_keyword(std::string_view text) {
  Keyword k;
  const std::vector<std::string_view> fields = split_fields(text.substr(1));
  for (char c : upper(fields[0])) {
    const bool blank = c == ' ' || c == '\t';
    if (blank && (k.name.empty() || k.name.back() == ' ')) continue;
    k.name += blank ? ' ' : c;
  }
  for (std::size_t i = 1; i < fields.size(); ++i) {
    if (fields[i].empty()) continue;
    Keyword::Parameter p;
    const std::size_t eq = fields[i].find('=');
    p.name = upper(trim(fields[i].substr(0, eq)));
    if (eq != std::string_view::npos) {
      p.has_value = true;
      std::string_view v = trim(fields[i].substr(eq + 1));
      if (v.size() >= 2 && v.front() == '"' && v.back() == '"') v = v.substr(1, v.size() - 2);
      p.value = std::string(v);
    }
    k.parameters.push_back(std::move(p));
  }
  return k;
}

// One entry of a set's data: where a block of it starts, a label, a GENERATE range, the name of
// another set, or (from the NSET= / ELSET= of *NODE / *ELEMENT) a run of items by index.
struct SetEntry {
  enum Kind : char { block, label, range, set_name, indices } kind = label;
  // block: a keyword line that adds to the set (it must name something); label: a; range: a..b by
  // step; set_name: a = index into InpReader::names_; indices: [a, b)
  long long a = 0, b = 0, step = 1;
  int line = 0;
};

struct SetDefinition {
  std::string name;  // as first written
  bool of_nodes = true;
  int first_line = 0;
  std::string origin;
  std::vector<SetEntry> entries;
  std::vector<int> members;
  bool expanded = false;
};

struct PendingElement {
  bool active = false;
  int line = 0;
  int fields = 0;  // label and nodes read so far
  long long label = 0;
  std::array<long long, 4> nodes{0, 0, 0, 0};
};

class InpReader {
 public:
  InpReader(const std::string& path, double memory_limit, std::string* error)
      : path_(path), memory_limit_(memory_limit), error_(error) {}

  bool read(ImportedSurface& out);

 private:
  enum class Block { none, heading, node, element, node_set, element_set, after_part };
  enum class PartState { none, inside, ended };

  bool fail(const std::string& message) {
    if (error_) *error_ = message;
    return false;
  }
  bool fail_at(int line, const std::string& message) { return fail(path_ + " line " + std::to_string(line) + ": " + message); }

  bool keyword(std::string_view text, int line);
  bool data(std::string_view text, int line, bool continues);
  bool node_line(const std::vector<std::string_view>& f, int line);
  bool element_fields(const std::vector<std::string_view>& f, int line, bool continues);
  bool finish_element();
  bool set_line(const std::vector<std::string_view>& f, int line);
  bool within_memory(int line);
  int set_for(const std::string& name, bool of_nodes, int line, const std::string& origin);
  void start_set_block(int line, bool with_indices);
  bool resolve(ImportedSurface& out);
  bool expand(SetDefinition& set, const std::unordered_map<long long, int>& index, std::vector<char>& in_set);

  std::string path_;
  double memory_limit_;
  std::string* error_;

  Block block_ = Block::none;
  PartState part_ = PartState::none;
  int part_line_ = 0, end_part_line_ = 0;
  bool content_before_part_ = false;
  int content_line_ = 0;

  // the block being read
  int block_set_ = -1;        // *NODE NSET= / *ELEMENT ELSET= / *NSET / *ELSET: its set
  bool block_generate_ = false;
  int block_corners_ = 4;
  int block_entity_ = 0;
  std::string block_type_;
  long long block_first_index_ = 0;
  PendingElement pending_;

  std::vector<Eigen::Vector3d> points_;
  std::vector<int> node_line_;
  std::unordered_map<long long, int> node_index_;
  struct Element {
    long long label;
    std::array<long long, 4> nodes;
    int corners, line, entity;
  };
  std::vector<Element> elements_;
  std::unordered_map<long long, int> element_index_;
  std::unordered_map<std::string, int> entity_of_;  // upper-case element set name -> entity
  int quads_ = 0, triangles_ = 0;

  std::vector<SetDefinition> sets_;
  std::unordered_map<std::string, int> node_set_of_, element_set_of_;  // upper-case name -> sets_
  std::vector<std::string> names_;  // set names written in set data lines (upper case)
  double set_entries_ = 0;
  double walk_ = 0;  // steps expanding the sets takes (see kMostNamesPerItem)
  double walk_limit() const {
    return kMostNamesPerItem * static_cast<double>(points_.size() + elements_.size()) + kNamesMargin;
  }
};

bool InpReader::within_memory(int line) {
  if (!(memory_limit_ > 0)) return true;
  const double need = static_cast<double>(points_.size()) * kBytesPerNode +
                      static_cast<double>(elements_.size()) * kBytesPerElement + set_entries_ * kBytesPerSetMember;
  if (need <= memory_limit_) return true;
  return fail_at(line, "reading the " + std::to_string(points_.size()) + " nodes, " + std::to_string(elements_.size()) +
                           " elements and " + std::to_string(static_cast<long long>(set_entries_)) +
                           " set members up to here would need about " + gigabytes(need) + " GB, more than the " +
                           gigabytes(memory_limit_) + " GB this machine allows");
}

int InpReader::set_for(const std::string& name, bool of_nodes, int line, const std::string& origin) {
  auto& of = of_nodes ? node_set_of_ : element_set_of_;
  const std::string key = upper(name);
  const auto it = of.find(key);
  if (it != of.end()) return it->second;  // a set written again gains the new members (as in Abaqus)
  SetDefinition s;
  s.name = name;
  s.of_nodes = of_nodes;
  s.first_line = line;
  s.origin = origin;
  sets_.push_back(std::move(s));
  of.emplace(key, static_cast<int>(sets_.size()) - 1);
  return static_cast<int>(sets_.size()) - 1;
}

// every keyword line that adds to a set must name something (a set written again gains members)
void InpReader::start_set_block(int line, bool with_indices) {
  SetEntry e;
  e.kind = SetEntry::block;
  e.line = line;
  sets_[static_cast<std::size_t>(block_set_)].entries.push_back(e);
  if (!with_indices) return;
  e.kind = SetEntry::indices;  // the *NODE / *ELEMENT block's items, counted as they are read
  e.a = e.b = block_first_index_;
  sets_[static_cast<std::size_t>(block_set_)].entries.push_back(e);
}

bool InpReader::keyword(std::string_view text, int line) {
  const Keyword k = parse_keyword(text);
  const std::string star = "*" + k.name;
  // parameters this keyword reads; any other is refused by name
  const auto check_parameters = [&](std::initializer_list<const char*> allowed) {
    for (const Keyword::Parameter& p : k.parameters) {
      bool known = false;
      for (const char* a : allowed) known = known || p.name == a;
      if (!known)
        return fail_at(line, star + " parameter " + shown(p.name) + (p.has_value ? "=" + shown(p.value) : std::string()) +
                                 " is not read: " + kNotRead);
    }
    return true;
  };
  const auto value_of = [&](const char* name) -> const Keyword::Parameter* {
    for (const Keyword::Parameter& p : k.parameters)
      if (p.name == name) return &p;
    return nullptr;
  };
  // the named parameter's value, required non-empty when present
  const auto named = [&](const char* name, std::string& value) {
    const Keyword::Parameter* p = value_of(name);
    if (!p) return true;
    if (!p->has_value || p->value.empty())
      return fail_at(line, star + ": " + std::string(name) + "= needs a name (e.g. " + name + "=CLAMPED)");
    value = p->value;
    return true;
  };
  const bool content = k.name == "NODE" || k.name == "ELEMENT" || k.name == "NSET" || k.name == "ELSET";
  if (content) {
    if (part_ == PartState::ended)
      return fail_at(line, star + " after *END PART (line " + std::to_string(end_part_line_) +
                               "): FlexFrame reads a single part, or a deck without *PART");
    if (part_ == PartState::none && !content_before_part_) {
      content_before_part_ = true;
      content_line_ = line;
    }
  }
  block_set_ = -1;
  block_generate_ = false;

  if (k.name == "HEADING") {
    if (!check_parameters({})) return false;
    block_ = Block::heading;
  } else if (k.name == "NODE") {
    if (!check_parameters({"NSET"})) return false;
    std::string nset;
    if (!named("NSET", nset)) return false;
    block_ = Block::node;
    block_first_index_ = static_cast<long long>(points_.size());
    if (!nset.empty()) {
      block_set_ = set_for(nset, true, line, "*NODE NSET= at line " + std::to_string(line));
      start_set_block(line, true);
    }
  } else if (k.name == "ELEMENT") {
    if (!check_parameters({"TYPE", "ELSET"})) return false;
    std::string type, elset;
    if (!named("TYPE", type) || !named("ELSET", elset)) return false;
    if (type.empty()) return fail_at(line, "*ELEMENT needs TYPE= (S4, S4R, S4R5, S3 or S3R)");
    const std::string t = upper(type);
    if (t == "S4" || t == "S4R" || t == "S4R5") {
      block_corners_ = 4;
    } else if (t == "S3" || t == "S3R") {
      block_corners_ = 3;
    } else {
      // Gmsh 4.8 writes its .inp with T3D2 lines and CPS3/CPS4 faces, whatever the mesh is for
      const bool gmsh_like = t.rfind("T3D", 0) == 0 || t.rfind("CPS", 0) == 0 || t.rfind("CPE", 0) == 0;
      return fail_at(line, "*ELEMENT TYPE=" + shown(type) +
                               " is not read: FlexFrame reads the shell elements S4, S4R, S4R5 (quads) and S3, S3R "
                               "(triangles) from an .inp" +
                               (gmsh_like ? std::string("; a deck exported by Gmsh (T3D2 lines, CPS3/CPS4 faces) is read "
                                                        "better as its .msh file")
                                          : std::string()));
    }
    block_type_ = t;
    block_ = Block::element;
    block_first_index_ = static_cast<long long>(elements_.size());
    block_entity_ = 0;
    if (!elset.empty()) {
      const auto it = entity_of_.emplace(upper(elset), static_cast<int>(entity_of_.size()) + 1).first;
      block_entity_ = it->second;
      block_set_ = set_for(elset, false, line, "*ELEMENT ELSET= at line " + std::to_string(line));
      start_set_block(line, true);
    }
  } else if (k.name == "NSET" || k.name == "ELSET") {
    const bool of_nodes = k.name == "NSET";
    const char* key = of_nodes ? "NSET" : "ELSET";
    if (!check_parameters({key, "GENERATE", "UNSORTED", "INTERNAL"})) return false;
    std::string name;
    if (!named(key, name)) return false;
    if (name.empty()) return fail_at(line, star + " needs " + key + "= (the set's name)");
    const Keyword::Parameter* g = value_of("GENERATE");
    if (g && g->has_value) return fail_at(line, star + ": GENERATE takes no value");
    block_generate_ = g != nullptr;
    block_ = of_nodes ? Block::node_set : Block::element_set;
    block_set_ = set_for(name, of_nodes, line, star + " at line " + std::to_string(line));
    start_set_block(line, false);
  } else if (k.name == "PART") {
    if (!check_parameters({"NAME"})) return false;
    if (part_ != PartState::none)
      return fail_at(line, "a second *PART (the first at line " + std::to_string(part_line_) +
                               "): FlexFrame reads a single part from an .inp");
    if (content_before_part_)
      return fail_at(line, "*PART after nodes, elements or sets outside a part (line " + std::to_string(content_line_) +
                               "): FlexFrame reads a single part, or a deck without *PART");
    part_ = PartState::inside;
    part_line_ = line;
    block_ = Block::none;
  } else if (k.name == "END PART") {
    if (!check_parameters({})) return false;
    if (part_ != PartState::inside) return fail_at(line, "*END PART without a *PART before it");
    part_ = PartState::ended;
    end_part_line_ = line;
    block_ = Block::after_part;
  } else if (k.name == "INCLUDE") {
    return fail_at(line, "*INCLUDE is not read: FlexFrame reads one .inp file and no file it names; "
                         "copy the included nodes, elements and sets into this file");
  } else {
    return fail_at(line, "*" + shown(k.name) + " is not read: " + kNotRead);
  }
  return true;
}

bool InpReader::node_line(const std::vector<std::string_view>& f, int line) {
  std::string why;
  long long label = 0;
  if (!parse_label(f[0], label, &why)) return fail_at(line, "*NODE: " + why);
  if (f.size() < 4)
    return fail_at(line, "node " + std::to_string(label) + " has " + std::to_string(f.size() - 1) +
                             " coordinates; a node needs its label and three coordinates x, y, z (a truncated line?)");
  if (f.size() > 4)
    return fail_at(line, "node " + std::to_string(label) +
                             ": fields after x, y, z (node normals) are not read; write the label and three coordinates");
  Eigen::Vector3d x;
  for (int k = 0; k < 3; ++k)
    if (!parse_coordinate(f[static_cast<std::size_t>(k) + 1], x[k], &why))
      return fail_at(line, "node " + std::to_string(label) + ": " + why);
  if (points_.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max() - 1))
    return fail_at(line, "more nodes than FlexFrame numbers (2^31 - 1)");
  const auto [it, inserted] = node_index_.emplace(label, static_cast<int>(points_.size()));
  if (!inserted)
    return fail_at(line, "node " + std::to_string(label) + " is defined twice (first at line " +
                             std::to_string(node_line_[static_cast<std::size_t>(it->second)]) + ")");
  points_.push_back(x);
  node_line_.push_back(line);
  if (block_set_ >= 0) {
    sets_[block_set_].entries.back().b = static_cast<long long>(points_.size());
    set_entries_ += 1;
  }
  return within_memory(line);
}

bool InpReader::element_fields(const std::vector<std::string_view>& f, int line, bool continues) {
  std::string why;
  for (const std::string_view field : f) {
    if (!pending_.active) {
      pending_ = PendingElement{};
      pending_.active = true;
      pending_.line = line;
    }
    long long v = 0;
    if (!parse_label(field, v, &why))
      return fail_at(line, pending_.fields == 0 ? "*ELEMENT: " + why
                                                : "element " + std::to_string(pending_.label) + ": " + why);
    if (pending_.fields == 0) {
      pending_.label = v;
    } else if (pending_.fields > block_corners_) {
      return fail_at(line, "element " + std::to_string(pending_.label) + " has more than the " +
                               std::to_string(block_corners_) + " nodes of an " + block_type_);
    } else {
      pending_.nodes[static_cast<std::size_t>(pending_.fields - 1)] = v;
    }
    ++pending_.fields;
  }
  if (pending_.fields == block_corners_ + 1) return finish_element();
  if (continues) return true;  // the element's nodes go on on the next line
  return finish_element();
}

bool InpReader::finish_element() {
  const PendingElement e = pending_;
  pending_.active = false;
  if (e.fields != block_corners_ + 1)
    return fail_at(e.line, "element " + std::to_string(e.label) + " has " + std::to_string(std::max(e.fields - 1, 0)) +
                               " of the " + std::to_string(block_corners_) + " nodes of an " + block_type_ +
                               " (a truncated line?)");
  if (elements_.size() >= static_cast<std::size_t>(std::numeric_limits<int>::max() - 1))
    return fail_at(e.line, "more elements than FlexFrame numbers (2^31 - 1)");
  const auto [it, inserted] = element_index_.emplace(e.label, static_cast<int>(elements_.size()));
  if (!inserted)
    return fail_at(e.line, "element " + std::to_string(e.label) + " is defined twice (first at line " +
                               std::to_string(elements_[static_cast<std::size_t>(it->second)].line) + ")");
  Element el{e.label, e.nodes, block_corners_, e.line, block_entity_};
  if (block_corners_ == 3) el.nodes[3] = 0;
  elements_.push_back(el);
  (block_corners_ == 4 ? quads_ : triangles_)++;
  if (block_set_ >= 0) {
    sets_[block_set_].entries.back().b = static_cast<long long>(elements_.size());
    set_entries_ += 1;
  }
  return within_memory(e.line);
}

bool InpReader::set_line(const std::vector<std::string_view>& f, int line) {
  SetDefinition& set = sets_[block_set_];
  const char* what = set.of_nodes ? "*NSET" : "*ELSET";
  std::string why;
  if (block_generate_) {
    if (f.size() < 2 || f.size() > 3)
      return fail_at(line, std::string(what) + ", GENERATE: a line is 'first, last' or 'first, last, step' (this one has " +
                               std::to_string(f.size()) + " fields)");
    SetEntry e;
    e.kind = SetEntry::range;
    e.line = line;
    if (!parse_label(f[0], e.a, &why) || !parse_label(f[1], e.b, &why)) return fail_at(line, std::string(what) + ": " + why);
    if (f.size() == 3) {
      const std::string_view s = f[2];
      const auto r = std::from_chars(s.data(), s.data() + s.size(), e.step);
      if (s.empty() || r.ec != std::errc() || r.ptr != s.data() + s.size() || e.step <= 0)
        return fail_at(line, std::string(what) + ", GENERATE: the step '" + shown(s) + "' is not a positive integer");
    }
    if (e.b < e.a)
      return fail_at(line, std::string(what) + ", GENERATE: the range ends (" + std::to_string(e.b) +
                               ") before it starts (" + std::to_string(e.a) + ")");
    set.entries.push_back(e);
  } else {
    for (const std::string_view field : f) {
      SetEntry e;
      e.line = line;
      const unsigned char c0 = field.empty() ? 0 : static_cast<unsigned char>(field.front());
      if (field.empty()) return fail_at(line, std::string(what) + ": an empty field");
      if (std::isdigit(c0) || c0 == '+' || c0 == '-' || c0 == '.') {
        if (!parse_label(field, e.a, &why)) return fail_at(line, std::string(what) + ": " + why);
      } else {
        std::string_view name = field;
        if (name.size() >= 2 && name.front() == '"' && name.back() == '"') name = name.substr(1, name.size() - 2);
        e.kind = SetEntry::set_name;
        e.a = static_cast<long long>(names_.size());
        names_.push_back(upper(name));
      }
      set.entries.push_back(e);
    }
  }
  set_entries_ += static_cast<double>(f.size());
  return within_memory(line);
}

bool InpReader::data(std::string_view text, int line, bool continues) {
  switch (block_) {
    case Block::heading:
      return true;
    case Block::none:
      return fail_at(line, "'" + shown(text) + "' is data before any keyword (an .inp line starts with *KEYWORD or is data of the keyword above it)");
    case Block::after_part:
      return fail_at(line, "'" + shown(text) + "' is data after *END PART");
    default:
      break;
  }
  const std::vector<std::string_view> f = split_fields(text);
  for (std::size_t i = 0; i < f.size(); ++i)
    if (f[i].empty()) return fail_at(line, "field " + std::to_string(i + 1) + " is empty ('" + shown(text) + "')");
  switch (block_) {
    case Block::node:
      return node_line(f, line);
    case Block::element:
      return element_fields(f, line, continues);
    default:
      return set_line(f, line);
  }
}

// The members of `set` as indices, each once, in order of first mention. Every label must name an
// item of the file; a range is walked label by label and stops at the first label that is not
// defined, so it takes at most `count` + 1 steps whatever its length. `in_set` (one flag per item,
// all 0) is shared by the sets and left all 0.
bool InpReader::expand(SetDefinition& set, const std::unordered_map<long long, int>& index, std::vector<char>& in_set) {
  const char* item = set.of_nodes ? "node" : "element";
  const auto add = [&](int i) {
    if (!in_set[static_cast<std::size_t>(i)]) {
      in_set[static_cast<std::size_t>(i)] = 1;
      set.members.push_back(i);
    }
  };
  const auto& sets_by_name = set.of_nodes ? node_set_of_ : element_set_of_;
  bool block_named_something = true;
  int block_line = set.first_line;
  bool ok = true;
  for (const SetEntry& e : set.entries) {
    if (!ok) break;
    switch (e.kind) {
      case SetEntry::block:
        if (!block_named_something) break;
        block_named_something = false;
        block_line = e.line;
        continue;
      case SetEntry::indices:
        for (long long i = e.a; i < e.b; ++i) add(static_cast<int>(i));
        block_named_something = block_named_something || e.b > e.a;
        continue;
      case SetEntry::label: {
        const auto it = index.find(e.a);
        if (it == index.end()) {
          ok = fail_at(e.line, "set '" + shown(set.name) + "' names " + item + " " + std::to_string(e.a) +
                                   ", which the file does not define");
          continue;
        }
        add(it->second);
        block_named_something = true;
        continue;
      }
      case SetEntry::range:
        for (long long label = e.a;; label += e.step) {
          const auto it = index.find(label);
          if (it == index.end()) {
            ok = fail_at(e.line, "set '" + shown(set.name) + "': GENERATE " + std::to_string(e.a) + ", " +
                                     std::to_string(e.b) + ", " + std::to_string(e.step) + " names " + item + " " +
                                     std::to_string(label) + ", which the file does not define");
            break;
          }
          add(it->second);
          if (e.b - label < e.step) break;  // the range's last label (and no overflow past e.b)
        }
        block_named_something = true;
        continue;
      case SetEntry::set_name: {
        const std::string& name = names_[static_cast<std::size_t>(e.a)];
        const auto it = sets_by_name.find(name);
        if (it == sets_by_name.end()) {
          ok = fail_at(e.line, "set '" + shown(set.name) + "' names '" + shown(name) + "', which is neither a " + item +
                                   " label nor a " + item + " set of the file");
          continue;
        }
        const SetDefinition& other = sets_[static_cast<std::size_t>(it->second)];
        if (!other.expanded) {  // resolve() expands the sets a set names first; a cycle is refused there
          ok = fail_at(e.line, "set '" + shown(set.name) + "' names set '" + shown(other.name) + "', which is not complete");
          continue;
        }
        walk_ += static_cast<double>(other.members.size());
        if (walk_ > walk_limit()) {
          ok = fail_at(e.line, "set '" + shown(set.name) + "' names set '" + shown(other.name) + "': the sets up to here " +
                                   "name more than " + std::to_string(static_cast<long long>(kMostNamesPerItem)) +
                                   " times the nodes and elements the file defines");
          continue;
        }
        for (int i : other.members) add(i);
        block_named_something = true;
        continue;
      }
    }
    // a block that named nothing
    ok = fail_at(block_line, "set '" + shown(set.name) + "' is empty here: this keyword line has no " + item +
                                 " under it");
  }
  for (int i : set.members) in_set[static_cast<std::size_t>(i)] = 0;
  if (!ok) return false;
  if (set.members.empty()) return fail_at(block_line, "set '" + shown(set.name) + "' is empty: it names no " + item);
  if (!block_named_something)
    return fail_at(block_line, "set '" + shown(set.name) + "' is empty here: this keyword line has no " + item +
                                   " under it");
  set.expanded = true;
  return true;
}

bool InpReader::resolve(ImportedSurface& out) {
  if (elements_.empty())
    return fail(path_ + ": no *ELEMENT of type S4, S4R, S4R5, S3 or S3R; a shell needs elements");
  // what expanding the sets will walk: a range stops at its first undefined label, so it takes at
  // most one step more than the items there are
  double& walk = walk_;
  for (const SetDefinition& set : sets_) {
    const double items = static_cast<double>(set.of_nodes ? points_.size() : elements_.size());
    for (const SetEntry& e : set.entries)
      walk += e.kind == SetEntry::range ? std::min(static_cast<double>((e.b - e.a) / e.step) + 1.0, items + 1.0) : 1.0;
  }
  if (walk > walk_limit()) {
    char n[32];
    std::snprintf(n, sizeof n, "%.3g", walk);
    return fail(path_ + ": its sets name " + n + " nodes and elements (GENERATE ranges counted by their length), more than " +
                std::to_string(static_cast<long long>(kMostNamesPerItem)) + " times the " +
                std::to_string(points_.size() + elements_.size()) + " nodes and elements it defines");
  }
  out.format = "Abaqus INP";
  out.file = path_;
  out.points = points_;
  out.elements.reserve(elements_.size());
  for (const Element& e : elements_) {
    ImportedElement el;
    el.entity = e.entity;
    el.where = "element " + std::to_string(e.label) + " (line " + std::to_string(e.line) + ")";
    for (int k = 0; k < e.corners; ++k) {
      const auto it = node_index_.find(e.nodes[static_cast<std::size_t>(k)]);
      if (it == node_index_.end())
        return fail_at(e.line, "element " + std::to_string(e.label) + " names node " +
                                   std::to_string(e.nodes[static_cast<std::size_t>(k)]) + ", which no *NODE defines");
      el.nodes[static_cast<std::size_t>(k)] = it->second;
    }
    out.elements.push_back(std::move(el));
  }
  // A set named in another is taken whole, wherever it is written: the sets a set names are
  // expanded before it (depth first, with an explicit stack, so that a long chain of sets cannot
  // exhaust the call stack); a set that names itself, directly or through others, is refused.
  // Node sets name only node sets, element sets only element sets.
  int node_sets = 0, element_sets = 0;
  std::vector<char> in_node_set(points_.size(), 0), in_element_set(elements_.size(), 0);
  enum : char { unvisited, open, expanded };
  std::vector<char> state(sets_.size(), unvisited);
  std::vector<std::size_t> cursor(sets_.size(), 0), stack;
  for (std::size_t first = 0; first < sets_.size(); ++first) {
    if (state[first] != unvisited) continue;
    state[first] = open;
    stack.assign(1, first);
    while (!stack.empty()) {
      const std::size_t t = stack.back();
      SetDefinition& set = sets_[t];
      const auto& by_name = set.of_nodes ? node_set_of_ : element_set_of_;
      bool descended = false;
      for (; cursor[t] < set.entries.size() && !descended; ++cursor[t]) {
        const SetEntry& e = set.entries[cursor[t]];
        if (e.kind != SetEntry::set_name) continue;
        const auto it = by_name.find(names_[static_cast<std::size_t>(e.a)]);
        if (it == by_name.end()) continue;  // expand() refuses it with its line
        const std::size_t r = static_cast<std::size_t>(it->second);
        if (state[r] == expanded) continue;
        if (state[r] == open)
          return fail_at(e.line, "set '" + shown(set.name) + "' names set '" + shown(sets_[r].name) + "', which " +
                                     (r == t ? std::string("is itself")
                                             : "contains '" + shown(set.name) + "' in turn (directly or through other sets)") +
                                     "; a set cannot contain itself");
        state[r] = open;
        stack.push_back(r);
        descended = true;
      }
      if (descended) continue;
      if (!expand(set, set.of_nodes ? node_index_ : element_index_, set.of_nodes ? in_node_set : in_element_set))
        return false;
      state[t] = expanded;
      stack.pop_back();
      set_entries_ += static_cast<double>(set.members.size());
      if (!within_memory(set.first_line)) return false;
      (set.of_nodes ? node_sets : element_sets)++;
    }
  }
  for (SetDefinition& s : sets_) {
    ImportedGroup g;
    g.name = s.name;
    g.dimension = s.of_nodes ? 0 : 2;
    (s.of_nodes ? g.nodes : g.elements) = std::move(s.members);
    g.origin = s.origin;
    out.groups.push_back(std::move(g));
  }
  const auto plural = [](long long n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  std::string note = "read " + plural(static_cast<long long>(points_.size()), "node", "nodes") + ", " +
                     plural(quads_, "quad", "quads") + " (S4/S4R/S4R5), " +
                     plural(triangles_, "triangle", "triangles") + " (S3/S3R), " +
                     plural(node_sets, "node set", "node sets") + " and " +
                     plural(element_sets, "element set", "element sets") + " from Abaqus INP";
  out.notes.push_back(note);
  return true;
}

bool InpReader::read(ImportedSurface& out) {
  std::error_code ec;
  if (std::filesystem::is_directory(path_, ec)) return fail(path_ + " is a directory, not an .inp file");
  // a regular file no larger than the memory limit (a FIFO would block the open below, /dev/zero never end)
  if (std::filesystem::exists(path_, ec))
    if (const std::string problem = input_file_problem(
            path_, memory_limit_ > 0 ? static_cast<std::uintmax_t>(memory_limit_) : 0, kMemoryLimitBound);
        !problem.empty())
      return fail(path_ + " " + problem);
  std::ifstream in(path_, std::ios::binary);
  if (!in) return fail("cannot open " + path_);
  std::string raw, keyword_text;
  int line = 0, keyword_line = 0;
  bool in_keyword = false;  // a keyword line ended with a comma: it goes on
  while (std::getline(in, raw)) {
    ++line;
    if (!raw.empty() && raw.back() == '\r') raw.pop_back();
    if (line == 1 && raw.rfind("\xEF\xBB\xBF", 0) == 0) raw.erase(0, 3);  // a UTF-8 byte order mark
    const std::string_view text = trim(raw);
    if (in_keyword) {
      keyword_text += text;
      if (ends_with_comma(text)) continue;
      in_keyword = false;
      if (!keyword(keyword_text, keyword_line)) return false;
      continue;
    }
    if (text.empty() || text.substr(0, 2) == "**") continue;
    if (text.front() == '*') {
      if (pending_.active && !finish_element()) return false;
      keyword_text = std::string(text);
      keyword_line = line;
      if (ends_with_comma(text)) {
        in_keyword = true;
        continue;
      }
      if (!keyword(keyword_text, keyword_line)) return false;
      continue;
    }
    if (!data(text, line, ends_with_comma(text))) return false;
  }
  if (in.bad()) return fail("reading " + path_ + " failed");
  if (in_keyword)
    return fail_at(keyword_line, "the keyword line ends with a comma, but the file ends before it goes on (truncated?)");
  if (pending_.active && !finish_element()) return false;
  if (part_ == PartState::inside)
    return fail_at(part_line_, "*PART has no *END PART: the file ends inside the part (truncated?)");
  return resolve(out);
}

}  // namespace

bool read_abaqus_inp(const std::string& path, ff::mesh::ImportedSurface& out, std::string* error,
                     double memory_limit_bytes) {
  ImportedSurface surface;
  InpReader reader(path, memory_limit_bytes, error);
  if (!reader.read(surface)) return false;
  out = std::move(surface);
  return true;
}

}  // namespace ff::io
