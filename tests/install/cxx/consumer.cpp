// A C++ program outside the project, built with find_package(surfkit): reads a mesh and prints
// "VERSION V E F genus N" (the C consumer's numbers), errors as an exception's message.
#include <surfkit/surfkit.h>

#include <cstdio>
#include <memory>
#include <stdexcept>
#include <string>

namespace {
struct mesh_deleter {
    void operator()(sk_mesh *m) const { sk_mesh_destroy(&m); }
};
using mesh_ptr = std::unique_ptr<sk_mesh, mesh_deleter>;

mesh_ptr read(const std::string &path)
{
    sk_error err;
    sk_mesh *m = nullptr;
    if (sk_mesh_read(path.c_str(), nullptr, &m, &err) != SK_OK)
        throw std::runtime_error(err.message);
    return mesh_ptr(m);
}
} // namespace

int main(int argc, char **argv)
{
    if (argc != 2) {
        std::fprintf(stderr, "usage: consumer_cxx MESH\n");
        return 2;
    }
    try {
        mesh_ptr mesh = read(argv[1]);
        sk_topology top{};
        sk_error err;
        if (sk_mesh_topology(mesh.get(), &top, nullptr, &err) != SK_OK)
            throw std::runtime_error(err.message);
        std::printf("%s V %zu E %zu F %zu genus %ld\n", sk_version(), top.vertices, top.edges,
                    top.faces, top.genus);
    } catch (const std::exception &e) {
        std::fprintf(stderr, "%s\n", e.what());
        return 1;
    }
    return 0;
}
