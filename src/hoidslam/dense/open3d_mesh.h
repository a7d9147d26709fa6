#pragma once
// Meshes between hoidslam's io::TriangleMesh (colours as bytes) and Open3D's (colours in [0, 1]), for the module's
// own files: Open3D stays out of its public headers.

#include <open3d/geometry/TriangleMesh.h>

#include "hoidslam/io/ply_file.h"

namespace hoidslam::dense {

open3d::geometry::TriangleMesh ToOpen3d(const io::TriangleMesh& mesh);
io::TriangleMesh FromOpen3d(const open3d::geometry::TriangleMesh& mesh);

}  // namespace hoidslam::dense
