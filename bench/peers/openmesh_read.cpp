// Peer for bench/all.sh (the read row): OpenMesh's own reader (OpenMesh::IO::read_mesh into a
// TriMesh_ArrayKernelT) on one mesh file, timed alone; prints "openmesh-read FACES SECONDS".
// Usage: openmesh_read MESH
#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>

#include <chrono>
#include <cstdio>

typedef OpenMesh::TriMesh_ArrayKernelT<> Mesh;

int main(int argc, char **argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: openmesh_read MESH\n");
        return 2;
    }
    Mesh mesh;
    OpenMesh::IO::Options opt;
    auto t0 = std::chrono::steady_clock::now();
    if (!OpenMesh::IO::read_mesh(mesh, argv[1], opt)) {
        std::fprintf(stderr, "openmesh_read: cannot read %s\n", argv[1]);
        return 1;
    }
    double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("openmesh-read %zu %.6f\n", (size_t)mesh.n_faces(), s);
    return 0;
}
