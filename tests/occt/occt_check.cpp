// occt_check: verifies surfkit's IGES and STEP files with an independent CAD kernel (Open CASCADE).
//
//   occt_check OUTDIR MESH [--flat] [--max-jump DEG] [--closed]
//
// Builds a patch network on MESH, exports IGES (split and degenerate triangles) and STEP into
// OUTDIR, reads each back with Open CASCADE and checks: no fail messages while loading, the face
// count, BRepCheck validity, every face evaluated at sample (u, v) against surfkit's evaluation
// (1e-9 relative to the model size), the normal jump across every shared edge of the STEP shell
// (below --max-jump degrees when given), and that the STEP shell is one edge-connected piece
// (closed when --closed). Prints one table row per file; exits 1 on any failure.
//
// --flat builds flat patches (triangles: linear, elevated to degree 4; quads: bilinear, elevated to
// bicubic), which share exact boundary curves; otherwise the VC1 surface of surfkit smooth.
#include <BRepCheck_Analyzer.hxx>
#include <BRep_Tool.hxx>
#include <GeomAPI_ProjectPointOnSurf.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Curve.hxx>
#include <Geom_Surface.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <Interface_CheckIterator.hxx>
#include <STEPControl_Reader.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_ListIteratorOfListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <XSControl_WorkSession.hxx>
#include <gp_Pnt.hxx>
#include <gp_Pnt2d.hxx>
#include <gp_Vec.hxx>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <sys/stat.h>
#include <vector>

extern "C" {
#include "surfkit/surfkit.h"
}

static bool build_patches(const sk_mesh *m, bool flat, sk_patch_set &out, std::string &why);

namespace {

struct result {
    size_t faces = 0;
    double max_dev = 0.0, max_jump = 0.0;
    size_t measured = 0, unmeasured = 0; /* normal-jump samples */
    size_t shared_edges = 0, components = 0, free_edges = 0;
    bool valid = false, load_ok = false;
};

double file_kb(const std::string &p)
{
    struct stat st;
    return stat(p.c_str(), &st) == 0 ? (double)st.st_size / 1024.0 : 0.0;
}

gp_Vec face_normal(const TopoDS_Face &f, const Handle(Geom_Surface) & s, double u, double v)
{
    gp_Pnt p;
    gp_Vec du, dv;
    s->D1(u, v, p, du, dv);
    gp_Vec n = du.Crossed(dv);
    if (n.Magnitude() > 0)
        n.Normalize();
    if (f.Orientation() == TopAbs_REVERSED)
        n.Reverse();
    return n;
}

bool load(const std::string &path, bool step, TopoDS_Shape &shape, bool &clean)
{
    if (step) {
        STEPControl_Reader r;
        if (r.ReadFile(path.c_str()) != IFSelect_RetDone)
            return false;
        clean = r.WS()->ModelCheckList().IsEmpty(Standard_True);
        r.TransferRoots();
        shape = r.OneShape();
    } else {
        IGESControl_Reader r;
        if (r.ReadFile(path.c_str()) != IFSelect_RetDone)
            return false;
        clean = r.WS()->ModelCheckList().IsEmpty(Standard_True);
        r.TransferRoots();
        shape = r.OneShape();
    }
    return !shape.IsNull();
}

result check(const std::string &path, bool step, const sk_patch_set &tensor, double size)
{
    result res;
    TopoDS_Shape shape;
    if (!load(path, step, shape, res.load_ok))
        return res;
    res.valid = BRepCheck_Analyzer(shape).IsValid();
    std::vector<TopoDS_Face> faces;
    for (TopExp_Explorer ex(shape, TopAbs_FACE); ex.More(); ex.Next())
        faces.push_back(TopoDS::Face(ex.Current()));
    res.faces = faces.size();
    for (size_t i = 0; i < faces.size() && i < tensor.count; ++i) {
        Handle(Geom_Surface) s = BRep_Tool::Surface(faces[i]);
        for (int a = 0; a <= 4; ++a)
            for (int b = 0; b <= 4; ++b) {
                /* non-dyadic parameters, so that no rounding coincidence hides a difference */
                double u = (a + 0.3) / 4.6, v = (b + 0.7) / 4.9, q[3];
                gp_Pnt p = s->Value(u, v);
                sk_patch_eval(&tensor, i, u, v, q, nullptr, nullptr, nullptr);
                double d = std::sqrt((p.X() - q[0]) * (p.X() - q[0]) + (p.Y() - q[1]) * (p.Y() - q[1]) +
                                     (p.Z() - q[2]) * (p.Z() - q[2]));
                res.max_dev = std::max(res.max_dev, d / size);
            }
    }
    if (!step)
        return res;
    // shared edges: normal jump, connectivity
    TopTools_IndexedDataMapOfShapeListOfShape ef;
    TopExp::MapShapesAndAncestors(shape, TopAbs_EDGE, TopAbs_FACE, ef);
    std::map<const void *, int> face_index;
    for (size_t i = 0; i < faces.size(); ++i)
        face_index[faces[i].TShape().get()] = (int)i;
    std::vector<int> parent(faces.size());
    for (size_t i = 0; i < parent.size(); ++i)
        parent[i] = (int)i;
    auto find = [&](int x) {
        while (parent[x] != x)
            x = parent[x] = parent[parent[x]];
        return x;
    };
    for (int e = 1; e <= ef.Extent(); ++e) {
        const TopTools_ListOfShape &fl = ef.FindFromIndex(e);
        if (BRep_Tool::Degenerated(TopoDS::Edge(ef.FindKey(e))))
            continue; // the collapsed side of a one-face triangle: a point, on one face only
        if (fl.Extent() != 2) {
            res.free_edges++;
            continue;
        }
        res.shared_edges++;
        TopoDS_Face f1 = TopoDS::Face(fl.First()), f2 = TopoDS::Face(fl.Last());
        parent[find(face_index[f1.TShape().get()])] = find(face_index[f2.TShape().get()]);
        const TopoDS_Edge &edge = TopoDS::Edge(ef.FindKey(e));
        double first, last;
        Handle(Geom_Curve) c = BRep_Tool::Curve(edge, first, last);
        if (c.IsNull())
            continue;
        Handle(Geom_Surface) s1 = BRep_Tool::Surface(f1), s2 = BRep_Tool::Surface(f2);
        for (int k = 1; k < 8; ++k) {
            double t = first + (last - first) * k / 8.0;
            gp_Pnt p = c->Value(t);
            /* (u, v) on each face: its pcurve of the edge, or else a projection; either must give
             * the edge point back, or the sample is not measured (and counted) */
            double uv[2][2];
            bool ok = true;
            const TopoDS_Face *fs[2] = {&f1, &f2};
            Handle(Geom_Surface) ss[2] = {s1, s2};
            for (int q = 0; q < 2 && ok; ++q) {
                double a, b;
                Handle(Geom2d_Curve) pc = BRep_Tool::CurveOnSurface(edge, *fs[q], a, b);
                bool found = false;
                if (!pc.IsNull()) {
                    gp_Pnt2d w = pc->Value(BRep_Tool::SameParameter(edge) ? t : a + (b - a) * k / 8.0);
                    uv[q][0] = w.X();
                    uv[q][1] = w.Y();
                    found = ss[q]->Value(uv[q][0], uv[q][1]).Distance(p) <= 1e-7 * size;
                }
                if (!found) {
                    GeomAPI_ProjectPointOnSurf pr(p, ss[q]);
                    if (pr.NbPoints() && pr.LowerDistance() <= 1e-7 * size) {
                        pr.LowerDistanceParameters(uv[q][0], uv[q][1]);
                        found = true;
                    }
                }
                ok = found;
            }
            if (!ok) {
                res.unmeasured++;
                continue;
            }
            gp_Vec n1 = face_normal(f1, s1, uv[0][0], uv[0][1]), n2 = face_normal(f2, s2, uv[1][0], uv[1][1]);
            double ang = std::atan2(n1.Crossed(n2).Magnitude(), n1.Dot(n2)) * 180.0 / M_PI;
            res.max_jump = std::max(res.max_jump, ang);
            res.measured++;
        }
    }
    for (size_t i = 0; i < faces.size(); ++i)
        res.components += find((int)i) == (int)i;
    return res;
}

} // namespace

int main(int argc, char **argv)
{
    if (argc < 3) {
        std::fprintf(stderr, "usage: occt_check OUTDIR MESH [--flat] [--max-jump DEG] [--closed]\n");
        return 2;
    }
    std::string outdir = argv[1], mesh_path = argv[2];
    bool flat = false, closed = false;
    double max_jump = -1;
    for (int i = 3; i < argc; ++i) {
        if (!std::strcmp(argv[i], "--flat"))
            flat = true;
        else if (!std::strcmp(argv[i], "--closed"))
            closed = true;
        else if (!std::strcmp(argv[i], "--max-jump") && i + 1 < argc)
            max_jump = std::atof(argv[++i]);
    }
    sk_error err;
    sk_mesh *mesh = nullptr;
    if (sk_mesh_read(mesh_path.c_str(), nullptr, &mesh, &err) != SK_OK) {
        std::fprintf(stderr, "occt_check: %s\n", err.message);
        return 1;
    }
    sk_patch_set patches = {};
    std::string why;
    if (!build_patches(mesh, flat, patches, why)) {
        std::fprintf(stderr, "occt_check: %s: %s\n", mesh_path.c_str(), why.c_str());
        return 1;
    }
    double size = sk_mesh_diagonal(mesh);
    const char *base = std::strrchr(mesh_path.c_str(), '/');
    std::string name = base ? base + 1 : mesh_path;
    name = name.substr(0, name.find('.'));
    int failures = 0;
    struct variant {
        const char *ext;
        bool step, degenerate;
    } variants[] = {{".igs", false, false}, {"-degenerate.igs", false, true}, {".step", true, false}};
    for (const variant &vr : variants) {
        sk_export_opts opts = {};
        opts.degenerate_triangles = vr.degenerate;
        opts.name = name.c_str();
        std::string path = outdir + "/" + name + vr.ext;
        sk_export_stats st = {};
        sk_status s = vr.step ? sk_export_step(path.c_str(), &patches, &opts, &st, &err)
                              : sk_export_iges(path.c_str(), &patches, &opts, &st, &err);
        if (s != SK_OK) {
            std::fprintf(stderr, "occt_check: export %s: %s\n", path.c_str(), err.message);
            return 1;
        }
        sk_patch_set tensor = {};
        sk_export_tensor_patches(&patches, &opts, &tensor, &err);
        size_t nt = tensor.count;
        result r = check(path, vr.step, tensor, size);
        sk_patch_set_free(&tensor);
        std::vector<std::string> bad;
        if (!r.load_ok)
            bad.push_back("fail messages on load");
        if (r.faces != nt)
            bad.push_back("face count " + std::to_string(r.faces) + " != " + std::to_string(nt));
        if (!r.valid && !vr.degenerate) // a collapsed side is a singular point BRepCheck may flag
            bad.push_back("BRepCheck: invalid shape");
        if (!(r.max_dev <= 1e-9))
            bad.push_back("deviation " + std::to_string(r.max_dev));
        if (vr.step) {
            if (r.unmeasured * 100 > r.measured + r.unmeasured) /* over 1%: no real measurement */
                bad.push_back(std::to_string(r.unmeasured) + " of " +
                              std::to_string(r.measured + r.unmeasured) +
                              " edge samples could not be located on both faces");
            if (r.components != 1)
                bad.push_back(std::to_string(r.components) + " connected pieces");
            if (closed && r.free_edges)
                bad.push_back(std::to_string(r.free_edges) + " free edges in a closed shell");
            if (max_jump >= 0 && !(r.max_jump <= max_jump))
                bad.push_back("normal jump " + std::to_string(r.max_jump) + " deg");
        }
        char jump[32] = "-", edges[32] = "-";
        if (vr.step) {
            std::snprintf(jump, sizeof jump, "%.2e deg", r.max_jump);
            std::snprintf(edges, sizeof edges, "%zu shared", r.shared_edges);
        }
        std::printf("| %-18s | %-16s | %6zu | %9.1f | %10.2e | %-13s | %-12s | %s |\n",
                    name.c_str(), vr.ext + 1, r.faces, file_kb(path), r.max_dev, jump, edges,
                    bad.empty() ? "ok" : "FAIL");
        for (const std::string &b : bad)
            std::printf("    %s: %s\n", path.c_str(), b.c_str());
        failures += !bad.empty();
    }
    sk_patch_set_free(&patches);
    sk_mesh_destroy(&mesh);
    return failures ? 1 : 0;
}

// Flat patches: linear triangles (degree 4) and bilinear quads (bicubic), corner ids = vertices.
static bool build_flat(const sk_mesh *m, sk_patch_set &out)
{
    sk_patch_set lin = {};
    bool ok = true;
    for (uint32_t f = 0; f < m->num_faces && ok; ++f) {
        if (m->f_deleted[f])
            continue;
        size_t n = sk_mesh_face_size(m, f);
        if (n != 3 && n != 4) {
            ok = false;
            break;
        }
        uint32_t h = m->f_halfedge[f];
        uint32_t ids[4];
        for (size_t k = 0; k < n; ++k, h = m->h_next[h])
            ids[k] = sk_from(m, h);
        double cp[4 * 3];
        if (n == 3) {
            const unsigned idx[3] = {sk_tri_index(1, 0, 0), sk_tri_index(1, 1, 0), sk_tri_index(1, 0, 1)};
            for (int k = 0; k < 3; ++k)
                std::memcpy(cp + 3 * idx[k], m->positions + 3 * ids[k], 3 * sizeof(double));
        } else {
            const unsigned idx[4] = {0, 1, 3, 2}; // (0,0) (1,0) (1,1) (0,1)
            for (int k = 0; k < 4; ++k)
                std::memcpy(cp + 3 * idx[k], m->positions + 3 * ids[k], 3 * sizeof(double));
        }
        sk_patch_set_clear(&lin);
        ok = sk_patch_set_add(&lin, n == 3 ? SK_PATCH_TRIANGLE : SK_PATCH_TENSOR, 1, 1, cp, ids,
                              nullptr, nullptr) == SK_OK &&
             sk_patch_elevate(&lin, 0, n == 3 ? 4 : 3, n == 3 ? 0 : 3, &out, nullptr) == SK_OK;
    }
    sk_patch_set_free(&lin);
    return ok;
}

static bool build_patches(const sk_mesh *m, bool flat, sk_patch_set &out, std::string &why)
{
    if (flat) {
        if (!build_flat(m, out)) {
            why = "flat patches need triangles and quads";
            return false;
        }
        return true;
    }
    sk_error err;
    sk_smooth *s = nullptr;
    /* G1 across every shared edge is what --max-jump checks: no G0 creases (the icosahedron's
     * 41.8-degree edges are above the default crease angle) */
    sk_smooth_opts o = {};
    o.crease_angle_deg = -1.0;
    if (sk_smooth_build(m, &o, &s, &err) != SK_OK) {
        why = err.message;
        return false;
    }
    out = s->surface; // take the surface over
    s->surface = sk_patch_set{};
    sk_smooth_destroy(&s);
    return true;
}
