// CGAL 5.5 peer for bench/deviation.sh: closest points with CGAL's AABB tree (the
// accelerate_distance_queries search tree on), the same queries as bench_deviation: every
// vertex of QUERY.off and the centroid of each of its faces, projected to SURFACE.off.
// Prints "cgal_aabb build_s query_s queries max_distance sum_distance".
//   cgal_closest SURFACE.off QUERY.off
#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <vector>

typedef CGAL::Simple_cartesian<double> K;
typedef K::Point_3 P;
typedef CGAL::Surface_mesh<P> SM;
typedef CGAL::AABB_face_graph_triangle_primitive<SM> Prim;
typedef CGAL::AABB_tree<CGAL::AABB_traits<K, Prim>> Tree;

static bool load(const char *path, SM &sm)
{
    std::ifstream in(path);
    return in && (in >> sm);
}

int main(int argc, char **argv)
{
    if (argc != 3) {
        std::cerr << "usage: cgal_closest SURFACE.off QUERY.off\n";
        return 2;
    }
    SM surf, q;
    if (!load(argv[1], surf) || !load(argv[2], q)) {
        std::cerr << "cannot read the meshes\n";
        return 1;
    }
    std::vector<P> pts;
    for (auto v : q.vertices())
        pts.push_back(q.point(v));
    for (auto f : q.faces()) { // centroid of the face (triangles: the same as bench_deviation)
        double c[3] = {0, 0, 0};
        int n = 0;
        for (auto v : CGAL::vertices_around_face(q.halfedge(f), q)) {
            const P &p = q.point(v);
            c[0] += p.x(), c[1] += p.y(), c[2] += p.z();
            ++n;
        }
        pts.push_back(P(c[0] / n, c[1] / n, c[2] / n));
    }
    auto t0 = std::chrono::steady_clock::now();
    Tree tree(faces(surf).first, faces(surf).second, surf);
    tree.accelerate_distance_queries();
    auto t1 = std::chrono::steady_clock::now();
    double mx = 0, sum = 0;
    for (const P &p : pts) {
        double d = std::sqrt(tree.squared_distance(p));
        mx = std::max(mx, d);
        sum += d;
    }
    auto t2 = std::chrono::steady_clock::now();
    std::printf("cgal_aabb %.3f %.3f %zu %.17g %.17g\n",
                std::chrono::duration<double>(t1 - t0).count(),
                std::chrono::duration<double>(t2 - t1).count(), pts.size(), mx, sum);
    return 0;
}
