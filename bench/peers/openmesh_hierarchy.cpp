// Peer for bench/hierarchy.sh: a level hierarchy with OpenMesh's decimater and ModIndependentSetsT.
// Each level: unlock every vertex, decimate() until no collapse is left (ModIndependentSetsT locks
// the one-ring of every kept vertex after a collapse, so each level collapses an independent set),
// garbage_collection(). Priority: ModQuadricT (OpenMesh needs one non-binary module; it orders the
// collapses greedily by quadric error instead of the paper's random order); ModNormalFlippingT
// refuses normal turns over 90 degrees like surfkit's default. Stops when a level removes less than
// 3% of the faces. Usage: openmesh_hierarchy MESH [--levels-table]
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Decimater/DecimaterT.hh>
#include <OpenMesh/Tools/Decimater/ModIndependentSetsT.hh>
#include <OpenMesh/Tools/Decimater/ModNormalFlippingT.hh>
#include <OpenMesh/Tools/Decimater/ModQuadricT.hh>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <vector>

typedef OpenMesh::TriMesh_ArrayKernelT<> Mesh;

static double now()
{
    using namespace std::chrono;
    return duration<double>(steady_clock::now().time_since_epoch()).count();
}

int main(int argc, char **argv)
{
    const char *path = nullptr;
    bool table = false;
    for (int i = 1; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--levels-table"))
            table = true;
        else
            path = argv[i];
    }
    if (!path) {
        std::fprintf(stderr, "usage: openmesh_hierarchy MESH [--levels-table]\n");
        return 2;
    }
    Mesh mesh;
    double t0 = now();
    if (!OpenMesh::IO::read_mesh(mesh, path)) {
        std::fprintf(stderr, "openmesh_hierarchy: cannot read %s\n", path);
        return 1;
    }
    double t_read = now() - t0;
    struct Level {
        size_t vertices, faces;
        double seconds;
    };
    std::vector<Level> levels;
    levels.push_back({mesh.n_vertices(), mesh.n_faces(), 0.0});

    t0 = now();
    mesh.request_vertex_status();
    mesh.request_edge_status();
    mesh.request_face_status();
    mesh.request_face_normals();
    mesh.update_face_normals();
    OpenMesh::Decimater::DecimaterT<Mesh> dec(mesh);
    OpenMesh::Decimater::ModQuadricT<Mesh>::Handle quadric;
    OpenMesh::Decimater::ModIndependentSetsT<Mesh>::Handle indep;
    OpenMesh::Decimater::ModNormalFlippingT<Mesh>::Handle flip;
    dec.add(quadric);
    dec.add(indep);
    dec.add(flip);
    dec.module(flip).set_max_normal_deviation(90.0);
    if (!dec.initialize()) {
        std::fprintf(stderr, "openmesh_hierarchy: decimater initialisation failed\n");
        return 1;
    }
    double t_setup = now() - t0;
    double total = t_setup;
    for (;;) {
        double t = now();
        size_t before = mesh.n_faces();
        for (auto v : mesh.vertices())
            mesh.status(v).set_locked(false);
        size_t collapses = dec.decimate();
        mesh.garbage_collection();
        double dt = now() - t;
        total += dt;
        if (collapses == 0)
            break;
        levels.push_back({mesh.n_vertices(), mesh.n_faces(), dt});
        if ((double)(before - mesh.n_faces()) < 0.03 * (double)before)
            break;
    }
    std::printf("openmesh ModIndependentSetsT hierarchy: %zu levels, %zu -> %zu faces, build %.3f s "
                "(read %.3f s)\n",
                levels.size(), levels.front().faces, levels.back().faces, total, t_read);
    if (table) {
        std::printf("\n| level | vertices | faces | ratio | seconds |\n|---:|---:|---:|---:|---:|\n");
        size_t L = levels.size();
        for (size_t k = 0; k < L; ++k) {
            double ratio = k ? (double)levels[k - 1].faces / (double)levels[k].faces : 0.0;
            std::printf("| %zu | %zu | %zu | %.3f | %.3f |\n", L - 1 - k, levels[k].vertices,
                        levels[k].faces, ratio, levels[k].seconds);
        }
    }
    return 0;
}
