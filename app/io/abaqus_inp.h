#pragma once
/// \file abaqus_inp.h
/// Shell meshes from Abaqus input decks (.inp). Debian ships no C++ library that reads them
/// (Gmsh 4.8 writes .inp but does not read it), so this reads the subset a shell mesh needs and
/// refuses the rest of the file by keyword and line (abaqus_inp.md):
/// - `*HEADING` (its lines skipped), `**` comments, `*NODE` (NSET=), `*ELEMENT` with TYPE = S4,
///   S4R, S4R5 (quads) or S3, S3R (triangles) (ELSET=), `*NSET` and `*ELSET` (labels, names of
///   sets written before, or GENERATE ranges; `*NSET, ELSET=` takes the nodes of an element set),
///   and one `*PART` ... `*END PART` around them.
/// - Keywords, parameters and set names are case-insensitive; a set keeps the spelling of its
///   first definition. A keyword line ending in a comma continues on the next line, and so does
///   an element whose nodes do not fit on one line.
/// - Node and element labels are positive integers in any order; points and elements are
///   numbered 0, 1, ... in file order. Elements may name nodes defined later in the file.
/// - Node sets become groups of dimension 0 (nodes), element sets groups of dimension 2
///   (elements); each set's members in order of first mention, each once. The ELSET= of an
///   `*ELEMENT` block is also the elements' `entity` (1, 2, ... in order of first use; 0 none).
/// Refused, naming the file and line: any other keyword (materials, sections, steps,
/// boundaries, assemblies, instances, other element types) and `*INCLUDE`; a parameter not
/// listed; duplicate labels; an element or set naming an undefined node, element or set; an
/// empty set; a node without three coordinates or with more fields; a non-finite coordinate or
/// one beyond 1e150; a label that is not a positive integer below 2^63; a GENERATE range with a
/// step <= 0 or its end before its start; a truncated element or keyword line; a deck with no
/// elements; and a deck whose nodes, elements and set members would need more than
/// memory_limit_bytes (0: no limit).

#include <string>

#include "core/mesh/imported_surface.h"

namespace ff::io {

/// Reads `path` into `out` (format "Abaqus INP", file = path). Returns false with a complete
/// sentence in *error ("<path> line N: ...", or "<path>: ..." for the file as a whole);
/// `out` is untouched on failure.
bool read_abaqus_inp(const std::string& path, ff::mesh::ImportedSurface& out, std::string* error,
                     double memory_limit_bytes = 0);

}  // namespace ff::io
