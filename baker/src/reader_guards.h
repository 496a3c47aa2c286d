// Checks run before OpenMesh's readers see a file, for inputs those readers mishandle (OpenMesh 9.0,
// as Debian ships it: with assertions on). Each guard was found by a test or by fuzzing load_mesh.
#pragma once

#include "stages.h"

#include <string>

namespace dng {
namespace baker {

/// kInvalidInput unless every PLY header element count is a plain number the file is large enough to
/// hold (OpenMesh trusts the counts: "element vertex banana" made it spin for 85 s and then throw), the
/// only list is a face's vertex_indices, first among its properties, each face's corner count fits in
/// the file (ASCII or binary), and in an ASCII file each vertex's x, y and z are finite numbers and
/// every other value the reader reads as a number up to the faces is a whole number of its type.
BakeStatus checkPlyHeader(const std::string& path);

/// kInvalidInput unless an ASCII OFF file's vertex and face counts are plain numbers the file can
/// hold (OpenMesh reads a negative count as a huge one and keeps going) after the keyword's line, as
/// OpenMesh reads them, each vertex starts with three finite decimal coordinates (six numbers with
/// NOFF's normal, across line ends as OpenMesh reads them), each face lists the vertices it claims and
/// the file holds as many vertices and faces as it declares; and unless a binary OFF's counts, vertex
/// records and faces fit in the file (OpenMesh reads as many binary faces as the count says, past the
/// end of the file).
BakeStatus checkOffHeader(const std::string& path);

/// kInvalidInput when an OBJ face lists a vertex without its vertex index ("f /1 2 3": OpenMesh's OBJ
/// reader asserts on that and aborts the process), or a vertex ("v") lacks three finite coordinates
/// (the reader drops such a vertex, and every later face index then names the wrong one).
BakeStatus checkObjLines(const std::string& path);

/// kInvalidInput when an STL (binary or ASCII) has a vertex coordinate that is not a finite number:
/// OpenMesh's reader keeps it, merged with another vertex, or drops its facet. *out_declared_facets
/// (not null): the facet count a binary STL declares, or -1 for ASCII or malformed files; OpenMesh's
/// reader silently drops facets it cannot use (degenerate ones), so loadMesh compares the two.
BakeStatus checkStlCoordinates(const std::string& path, long long* out_declared_facets);

} // namespace baker
} // namespace dng
