// build_tree IN OUT.cstree: the cluster tree of a point cloud, saved as `clustersurf reconstruct
// IN -o OUT.cstree` saves it. Links clustersurf::tree only (no OpenVDB, no Embree).

#include <clustersurf/cluster/cluster_tree.hpp>
#include <clustersurf/cluster/tree_file.hpp>
#include <clustersurf/core/errors.hpp>
#include <clustersurf/io/point_cloud_io.hpp>
#include <clustersurf/surface/orientation.hpp>

#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: build_tree IN OUT.cstree\n";
    return 2;
  }
  try {
    const clustersurf::PointCloud cloud = clustersurf::read_point_cloud(argv[1]);
    clustersurf::ClusterTree tree = clustersurf::build_cluster_tree(cloud);
    clustersurf::orient_tree(tree, cloud);
    clustersurf::save_tree(argv[2], tree);
    std::cout << tree.nodes.size() << " nodes -> " << argv[2] << "\n";
    return 0;
  } catch (const clustersurf::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 1;
  }
}
