// The exact relaxation of the edge deletion's count (issue 12, near-minimal deletions): the minimum
// T-join of the mesh's edge graph, T = the interior vertices in an even number of faces, every edge
// weight 1, boundary vertices free to stay even (they absorb a path end).
//
// A T-join J is an edge set with odd degree exactly at T; deleting the edges of any edge deletion
// makes every even interior vertex odd and keeps the others' parity, so its deleted edges are a
// T-join with the boundary free: min |J| is a lower bound on the deleted edges, tighter than
// #even / 2 (Edmonds & Johnson, "Matching, Euler tours and the Chinese postman", 1973: the T-join
// problem as a perfect matching). The boundary vertices are made one free blob: edges with both
// ends on the boundary weigh 0, and a chain of weight-0 virtual edges joins all boundary vertices;
// if |T| is odd one boundary vertex joins T (the blob absorbs any parity).
//
// Reduction to a minimum-weight perfect matching (the vertex gadget): vertex v of degree d gets one
// node per incident edge, plus one dummy when d + [v in T] is odd; the nodes of v form a clique of
// weight 0 (edges not in J pair up inside v), and edge e = uv joins the node of e at u with the node
// of e at v with weight w(e) (matched: e in J). A perfect matching leaves deg_J(v) of v's nodes to
// external edges and pairs the rest, so deg_J(v) = d + dummy (mod 2) = [v in T]. Solved exactly
// with LEMON's MaxWeightedPerfectMatching on the negated weights.
//
// Usage: tjoin_lemon MESH.off ...   prints per mesh: name, #even, bound (ceil(#even / 2)), minimum
// T-join, CPU seconds of the matching.
#include <lemon/list_graph.h>
#include <lemon/matching.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

namespace {

// the weight of a forbidden edge in the second solve: used only where no other T-join exists
constexpr int SK_FORBIDDEN_WEIGHT = 1000;

struct Mesh {
    size_t nv = 0;
    std::vector<double> pos;
    std::vector<uint32_t> tri;
};

// the corner angle at a between a-b and a-c
double angle(const Mesh &m, uint32_t a, uint32_t b, uint32_t c)
{
    double x[3], y[3], dot = 0, xx = 0, yy = 0;
    for (int i = 0; i < 3; ++i) {
        x[i] = m.pos[3 * b + i] - m.pos[3 * a + i];
        y[i] = m.pos[3 * c + i] - m.pos[3 * a + i];
        dot += x[i] * y[i];
        xx += x[i] * x[i];
        yy += y[i] * y[i];
    }
    double n = std::sqrt(xx * yy);
    return n > 0 ? std::acos(std::max(-1.0, std::min(1.0, dot / n))) : 0.0;
}

bool next_line(std::ifstream &in, std::string &line)
{
    while (std::getline(in, line)) {
        size_t c = line.find('#');
        if (c != std::string::npos)
            line.resize(c);
        if (line.find_first_not_of(" \t\r") != std::string::npos)
            return true;
    }
    return false;
}

bool read_off(const char *path, Mesh &m)
{
    std::ifstream in(path);
    std::string line;
    if (!next_line(in, line))
        return false;
    std::istringstream head(line);
    std::string magic;
    head >> magic;
    size_t nv = 0, nf = 0;
    if (magic == "OFF") {
        if (!(head >> nv)) {
            if (!next_line(in, line))
                return false;
            std::istringstream c(line);
            c >> nv >> nf;
        } else {
            head >> nf;
        }
    } else {
        return false;
    }
    for (size_t i = 0; i < nv; ++i) {
        if (!next_line(in, line))
            return false;
        std::istringstream p(line);
        double x = 0, y = 0, z = 0;
        p >> x >> y >> z;
        m.pos.insert(m.pos.end(), {x, y, z});
    }
    m.nv = nv;
    for (size_t f = 0; f < nf; ++f) {
        if (!next_line(in, line))
            return false;
        std::istringstream s(line);
        size_t k = 0;
        s >> k;
        std::vector<uint32_t> poly(k);
        for (auto &x : poly)
            s >> x;
        for (size_t i = 1; i + 1 < k; ++i) { // fans of polygons (the shared meshes are triangles)
            m.tri.push_back(poly[0]);
            m.tri.push_back(poly[i]);
            m.tri.push_back(poly[i + 1]);
        }
    }
    return true;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 2) {
        std::fprintf(stderr, "usage: tjoin_lemon MESH.off ...\n");
        return 2;
    }
    std::printf("%-14s %8s %8s %10s %18s %8s\n", "mesh", "#even", "bound", "min T-join",
                "avoiding (forced)", "cpu s");
    for (int a = 1; a < argc; ++a) {
        Mesh m;
        if (!read_off(argv[a], m)) {
            std::fprintf(stderr, "tjoin_lemon: cannot read %s\n", argv[a]);
            return 1;
        }
        std::string name = argv[a];
        name = name.substr(name.find_last_of('/') + 1);
        name = name.substr(0, name.find_last_of('.'));
        // edges and their face counts
        std::unordered_map<uint64_t, uint32_t> eid;
        std::vector<uint32_t> eu, ev, efaces, eopp;
        std::vector<uint32_t> faces(m.nv, 0);
        for (size_t t = 0; t < m.tri.size(); t += 3)
            for (int i = 0; i < 3; ++i) {
                uint32_t x = m.tri[t + i], y = m.tri[t + (i + 1) % 3], z = m.tri[t + (i + 2) % 3];
                faces[x]++;
                uint64_t key = (uint64_t)std::min(x, y) << 32 | std::max(x, y);
                auto it = eid.find(key);
                if (it == eid.end()) {
                    eid.emplace(key, (uint32_t)eu.size());
                    eu.push_back(std::min(x, y));
                    ev.push_back(std::max(x, y));
                    efaces.push_back(1);
                    eopp.insert(eopp.end(), {z, UINT32_MAX});
                } else {
                    efaces[it->second]++;
                    eopp[2 * it->second + 1] = z;
                }
            }
        std::vector<char> bnd(m.nv, 0), inT(m.nv, 0);
        for (size_t e = 0; e < eu.size(); ++e)
            if (efaces[e] == 1)
                bnd[eu[e]] = bnd[ev[e]] = 1;
        size_t n_even = 0;
        std::vector<uint32_t> bverts;
        for (uint32_t v = 0; v < m.nv; ++v) {
            if (bnd[v])
                bverts.push_back(v);
            else if (faces[v] && faces[v] % 2 == 0) {
                inT[v] = 1;
                n_even++;
            }
        }
        // forbidden as in the library (src/smooth/edge_deletion.c): deleting the edge makes a quad
        // corner (the sum of the two triangle angles at an end) above 160 degrees
        std::vector<char> forbid(eu.size(), 0);
        const double max_corner = 160.0 * 3.14159265358979323846 / 180.0;
        for (size_t e = 0; e < eu.size(); ++e) {
            uint32_t a = eu[e], b = ev[e], c = eopp[2 * e], d = eopp[2 * e + 1];
            if (efaces[e] != 2 || d == UINT32_MAX)
                continue;
            forbid[e] = angle(m, a, b, c) + angle(m, a, b, d) > max_corner ||
                        angle(m, b, a, c) + angle(m, b, a, d) > max_corner;
        }
        std::vector<int> ew;
        for (size_t e = 0; e < eu.size(); ++e)
            ew.push_back(bnd[eu[e]] && bnd[ev[e]] ? 0 : 1);
        for (size_t i = 0; i + 1 < bverts.size(); ++i) { // the blob's chain
            eu.push_back(bverts[i]);
            ev.push_back(bverts[i + 1]);
            ew.push_back(0);
        }
        if ((n_even & 1u) && !bverts.empty())
            inT[bverts[0]] ^= 1;
        // the gadget, solved for the weights wt: the edges of the minimum T-join (weight > 0)
        // and how many of them are forbidden
        auto solve = [&](const std::vector<int> &wt, long &edges, long &forbidden, double &cpu) {
            std::clock_t c0 = std::clock();
            lemon::ListGraph g;
            std::vector<std::vector<lemon::ListGraph::Node>> port(m.nv);
            std::vector<uint32_t> deg(m.nv, 0);
            for (size_t e = 0; e < eu.size(); ++e) {
                deg[eu[e]]++;
                deg[ev[e]]++;
            }
            lemon::ListGraph::EdgeMap<int> w(g);
            for (uint32_t v = 0; v < m.nv; ++v) {
                size_t n = deg[v] + ((deg[v] + inT[v]) & 1u);
                for (size_t i = 0; i < n; ++i)
                    port[v].push_back(g.addNode());
                for (size_t i = 0; i < n; ++i)
                    for (size_t j = i + 1; j < n; ++j)
                        w[g.addEdge(port[v][i], port[v][j])] = 0;
            }
            std::vector<uint32_t> used(m.nv, 0);
            std::vector<lemon::ListGraph::Edge> ext;
            for (size_t e = 0; e < eu.size(); ++e) {
                auto x = port[eu[e]][used[eu[e]]++], y = port[ev[e]][used[ev[e]]++];
                auto ge = g.addEdge(x, y);
                w[ge] = -wt[e];
                ext.push_back(ge);
            }
            lemon::MaxWeightedPerfectMatching<lemon::ListGraph, lemon::ListGraph::EdgeMap<int>>
                mwpm(g, w);
            bool ok = mwpm.run();
            edges = forbidden = 0;
            for (size_t e = 0; ok && e < ext.size(); ++e)
                if (mwpm.matching(ext[e]) && wt[e] > 0) {
                    edges++;
                    forbidden += e < forbid.size() && forbid[e];
                }
            cpu = double(std::clock() - c0) / CLOCKS_PER_SEC;
            return ok;
        };
        long j1 = 0, f1 = 0, j2 = 0, f2 = 0;
        double cpu1 = 0, cpu2 = 0;
        bool ok1 = solve(ew, j1, f1, cpu1);
        std::vector<int> ewf = ew;
        for (size_t e = 0; e < forbid.size(); ++e)
            if (forbid[e] && ewf[e] > 0)
                ewf[e] = SK_FORBIDDEN_WEIGHT;
        bool ok2 = solve(ewf, j2, f2, cpu2);
        if (!ok1 || !ok2) {
            std::printf("%-14s %8zu %8zu %10s %18s %8.2f\n", name.c_str(), n_even,
                        (n_even + 1) / 2, "none", "none", cpu1 + cpu2);
            continue;
        }
        std::printf("%-14s %8zu %8zu %10ld %11ld (%4ld) %8.2f\n", name.c_str(), n_even,
                    (n_even + 1) / 2, j1, j2, f2, cpu1 + cpu2);
        std::fflush(stdout);
    }
    return 0;
}
