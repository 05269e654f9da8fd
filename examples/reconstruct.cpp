// reconstruct IN OUT.ply: a point cloud to a mesh of its surface, through the installed library.
// Writes the bytes `clustersurf reconstruct IN --mesh OUT.ply` writes: both call
// clustersurf::reconstruct() with the default options.

#include <clustersurf/clustersurf.hpp>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: reconstruct IN OUT.ply\n";
    return 2;
  }
  try {
    clustersurf::ReadOptions read;
    read.warn = [](const std::string& message) { std::cerr << "warning: " << message << "\n"; };
    const clustersurf::PointCloud cloud = clustersurf::read_point_cloud(argv[1], read);

    const clustersurf::Reconstruction result = clustersurf::reconstruct(cloud);  // build, orient, mesh, trim
    clustersurf::write_triangle_mesh(argv[2], result.mesh->mesh);

    const clustersurf::TreeSummary summary = clustersurf::summarize(result.tree);
    std::cout << cloud.size() << " points, " << summary.leaves << " leaves, " << result.mesh->mesh.triangles.rows()
              << " triangles -> " << argv[2] << "\n";
    return 0;
  } catch (const clustersurf::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
