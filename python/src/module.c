/* surfkit._core: the C extension under the surfkit package (surfkit/__init__.py is the API).
 * Converts between numpy arrays and calls.h, which holds every call into libsurfkit; those
 * calls run with the GIL released. A library error becomes surfkit.Error carrying the library's
 * one-line message (and .status, the status name). */
#define PY_SSIZE_T_CLEAN
#include <Python.h>
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

#include "calls.h"

#include <string.h>

static PyObject *sk_py_error; /* surfkit.Error */

static PyObject *raise_status(sk_status st, const sk_error *err)
{
    PyObject *exc = PyObject_CallFunction(sk_py_error, "s", err->message[0] ? err->message
                                                                             : sk_status_string(st));
    if (!exc)
        return NULL;
    PyObject *name = PyUnicode_FromString(sk_status_string(st));
    if (name) {
        PyObject_SetAttrString(exc, "status", name);
        Py_DECREF(name);
    }
    PyErr_SetObject(sk_py_error, exc);
    Py_DECREF(exc);
    return NULL;
}

/* A C-contiguous array of the given type and shape (-1: any extent); NULL with TypeError. */
static void *array_data(PyObject *obj, const char *what, int type, int ndim, npy_intp d0,
                        npy_intp d1, npy_intp *n0)
{
    if (!PyArray_Check(obj)) {
        PyErr_Format(PyExc_TypeError, "%s must be a numpy array", what);
        return NULL;
    }
    PyArrayObject *a = (PyArrayObject *)obj;
    if (PyArray_TYPE(a) != type || PyArray_NDIM(a) != ndim || !PyArray_IS_C_CONTIGUOUS(a) ||
        (d0 >= 0 && PyArray_DIM(a, 0) != d0) || (ndim > 1 && PyArray_DIM(a, 1) != d1)) {
        PyErr_Format(PyExc_TypeError, "%s has the wrong dtype, shape or layout", what);
        return NULL;
    }
    if (n0)
        *n0 = PyArray_DIM(a, 0);
    return PyArray_DATA(a);
}

/* (vertices (V,3) float64, offsets (F+1,) uint32, indices uint32[, normals, uvs]) -> borrowed
 * skpy_mesh; normals/uvs may be None. */
static int parse_mesh(PyObject *v, PyObject *off, PyObject *idx, PyObject *nrm, PyObject *uv,
                      skpy_mesh *m)
{
    memset(m, 0, sizeof *m);
    npy_intp nv, no, ni;
    if (!(m->positions = array_data(v, "vertices", NPY_FLOAT64, 2, -1, 3, &nv)) ||
        !(m->offsets = array_data(off, "offsets", NPY_UINT32, 1, -1, 0, &no)) ||
        !(m->indices = array_data(idx, "indices", NPY_UINT32, 1, -1, 0, &ni)))
        return -1;
    if (no < 1 || m->offsets[0] != 0 || (npy_intp)m->offsets[no - 1] != ni) {
        PyErr_SetString(PyExc_ValueError, "face offsets do not match the indices");
        return -1;
    }
    for (npy_intp f = 0; f + 1 < no; ++f)
        if (m->offsets[f + 1] < m->offsets[f]) {
            PyErr_SetString(PyExc_ValueError, "face offsets must not decrease");
            return -1;
        }
    m->nv = (size_t)nv;
    m->nf = (size_t)(no - 1);
    if (nrm && nrm != Py_None &&
        !(m->normals = array_data(nrm, "normals", NPY_FLOAT64, 2, nv, 3, NULL)))
        return -1;
    if (uv && uv != Py_None && !(m->uvs = array_data(uv, "uv", NPY_FLOAT64, 2, nv, 2, NULL)))
        return -1;
    return 0;
}

static PyObject *new_array(int nd, npy_intp d0, npy_intp d1, int type, const void *src,
                           size_t elem)
{
    npy_intp dims[2] = {d0, d1};
    PyObject *a = PyArray_SimpleNew(nd, dims, type);
    if (a && src && d0 * (nd > 1 ? d1 : 1) > 0)
        memcpy(PyArray_DATA((PyArrayObject *)a), src, (size_t)(d0 * (nd > 1 ? d1 : 1)) * elem);
    return a;
}

static PyObject *py_read(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *path_obj;
    if (!PyArg_ParseTuple(args, "O&", PyUnicode_FSConverter, &path_obj))
        return NULL;
    skpy_mesh m;
    sk_error err = {0};
    sk_status st;
    Py_BEGIN_ALLOW_THREADS
    st = skpy_read(PyBytes_AS_STRING(path_obj), &m, &err);
    Py_END_ALLOW_THREADS
    Py_DECREF(path_obj);
    if (st < 0)
        return raise_status(st, &err);
    npy_intp nv = (npy_intp)m.nv, nf = (npy_intp)m.nf;
    PyObject *v = new_array(2, nv, 3, NPY_FLOAT64, m.positions, sizeof(double));
    PyObject *o = new_array(1, nf + 1, 0, NPY_UINT32, m.offsets, sizeof(uint32_t));
    PyObject *i = new_array(1, (npy_intp)m.offsets[m.nf], 0, NPY_UINT32, m.indices, sizeof(uint32_t));
    PyObject *n = m.normals ? new_array(2, nv, 3, NPY_FLOAT64, m.normals, sizeof(double))
                            : (Py_INCREF(Py_None), Py_None);
    PyObject *u = m.uvs ? new_array(2, nv, 2, NPY_FLOAT64, m.uvs, sizeof(double))
                        : (Py_INCREF(Py_None), Py_None);
    skpy_mesh_free(&m);
    if (!v || !o || !i || !n || !u) {
        Py_XDECREF(v), Py_XDECREF(o), Py_XDECREF(i), Py_XDECREF(n), Py_XDECREF(u);
        return NULL;
    }
    return Py_BuildValue("(NNNNN)", v, o, i, n, u);
}

static PyObject *py_write(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *path_obj, *v, *o, *i, *n, *u;
    if (!PyArg_ParseTuple(args, "O&OOOOO", PyUnicode_FSConverter, &path_obj, &v, &o, &i, &n, &u))
        return NULL;
    skpy_mesh m;
    if (parse_mesh(v, o, i, n, u, &m)) {
        Py_DECREF(path_obj);
        return NULL;
    }
    sk_error err = {0};
    sk_status st;
    Py_BEGIN_ALLOW_THREADS
    st = skpy_write(PyBytes_AS_STRING(path_obj), &m, &err);
    Py_END_ALLOW_THREADS
    Py_DECREF(path_obj);
    if (st < 0)
        return raise_status(st, &err);
    Py_RETURN_NONE;
}

static PyObject *py_info(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *v, *o, *i;
    if (!PyArg_ParseTuple(args, "OOO", &v, &o, &i))
        return NULL;
    skpy_mesh m;
    if (parse_mesh(v, o, i, NULL, NULL, &m))
        return NULL;
    skpy_info info;
    sk_error err = {0};
    sk_status st;
    Py_BEGIN_ALLOW_THREADS
    st = skpy_info_compute(&m, &info, &err);
    Py_END_ALLOW_THREADS
    if (st < 0)
        return raise_status(st, &err);
    return Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:n,s:l,s:l}", "vertices",
                         (Py_ssize_t)info.top.vertices, "faces", (Py_ssize_t)info.top.faces,
                         "triangles", (Py_ssize_t)info.triangles, "quads", (Py_ssize_t)info.quads,
                         "edges", (Py_ssize_t)info.top.edges, "boundary_edges",
                         (Py_ssize_t)info.boundary_edges, "boundary_loops",
                         (Py_ssize_t)info.top.boundary_loops, "components",
                         (Py_ssize_t)info.top.components, "euler_characteristic",
                         info.top.euler_characteristic, "genus", info.top.genus);
}

static PyObject *py_parametrize(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *v, *o, *i;
    const char *method, *boundary;
    unsigned long long seed;
    Py_ssize_t steps;
    if (!PyArg_ParseTuple(args, "OOOszKn", &v, &o, &i, &method, &boundary, &seed, &steps))
        return NULL;
    if (steps < 0) {
        PyErr_SetString(PyExc_ValueError, "steps must not be negative");
        return NULL;
    }
    skpy_mesh m;
    if (parse_mesh(v, o, i, NULL, NULL, &m))
        return NULL;
    PyObject *uv = new_array(2, (npy_intp)m.nv, 2, NPY_FLOAT64, NULL, 0);
    if (!uv)
        return NULL;
    skpy_param_args a = {method, boundary, (uint64_t)seed, (size_t)steps};
    sk_param_metrics pm;
    sk_error err = {0};
    sk_status st;
    double *uvd = PyArray_DATA((PyArrayObject *)uv);
    memset(uvd, 0, m.nv * 2 * sizeof(double));
    Py_BEGIN_ALLOW_THREADS
    st = skpy_parametrize(&m, &a, uvd, &pm, &err);
    Py_END_ALLOW_THREADS
    if (st < 0) {
        Py_DECREF(uv);
        return raise_status(st, &err);
    }
    return Py_BuildValue("(N{s:n,s:n,s:d,s:d,s:d,s:d,s:d,s:d,s:n})", uv, "faces",
                         (Py_ssize_t)pm.faces, "flipped", (Py_ssize_t)pm.flipped, "mips_sum",
                         pm.mips_sum, "mips_mean", pm.mips_mean, "conformal_mean",
                         pm.conformal_mean, "conformal_max", pm.conformal_max, "area_log_mean",
                         pm.area_log_mean, "stretch_max", pm.stretch_max,
                         "boundary_self_intersections", (Py_ssize_t)pm.boundary_self_intersections);
}

static PyObject *surface_dict(const skpy_surface *s)
{
    npy_intp np_ = (npy_intp)s->num_patches;
    const sk_continuity_report *r = &s->report;
    PyObject *report = Py_BuildValue(
        "{s:n,s:n,s:d,s:d,s:d,s:d,s:(II),s:d,s:d,s:n,s:n,s:O,s:O,s:d,s:I,s:d,s:n,s:d,s:I,s:d}",
        "interior_edges",
        (Py_ssize_t)r->interior_edges, "samples", (Py_ssize_t)r->samples, "max_gap", r->max_gap,
        "mean_gap", r->mean_gap, "max_normal_jump_deg", r->max_normal_jump_deg,
        "mean_normal_jump_deg", r->mean_normal_jump_deg, "worst_edge_vertices",
        r->worst_edge_vertices[0], r->worst_edge_vertices[1], "max_vertex_error",
        r->max_vertex_error, "max_normal_error_deg", r->max_normal_error_deg, "singular_patches",
        (Py_ssize_t)r->singular_patches, "uncertified_patches",
        (Py_ssize_t)r->uncertified_patches, "pass_g1", r->pass_g1 ? Py_True : Py_False,
        "pass_gap", r->pass_gap ? Py_True : Py_False, "max_overshoot", r->max_overshoot,
        "max_overshoot_patch", (unsigned)r->max_overshoot_patch, "mean_overshoot",
        r->mean_overshoot, "overshoot_patches", (Py_ssize_t)r->overshoot_patches,
        "max_fairness_deg", r->max_fairness_deg, "max_fairness_patch",
        (unsigned)r->max_fairness_patch, "mean_fairness_deg", r->mean_fairness_deg);
    const sk_smooth_stats *t = &s->stats;
    PyObject *stats = Py_BuildValue("{s:n,s:n,s:n,s:n,s:n,s:n,s:n}", "deleted_edges",
                                    (Py_ssize_t)t->deletion.deleted_edges, "lower_bound",
                                    (Py_ssize_t)t->deletion.lower_bound, "triangles",
                                    (Py_ssize_t)t->deletion.triangles, "quads",
                                    (Py_ssize_t)t->deletion.quads, "split_edges",
                                    (Py_ssize_t)t->split_edges, "failed_vertices",
                                    (Py_ssize_t)t->failed_vertices, "angle_violations",
                                    (Py_ssize_t)t->angle_violations);
    PyObject *points = new_array(2, (npy_intp)s->num_points, 3, NPY_FLOAT64, s->points,
                                 sizeof(double));
    PyObject *kind = new_array(1, np_, 0, NPY_UINT8, s->kind, 1);
    PyObject *degree = new_array(1, np_, 0, NPY_UINT8, s->degree, 1);
    PyObject *first = new_array(1, np_, 0, NPY_UINT32, s->first, sizeof(uint32_t));
    PyObject *corners = new_array(2, np_, 4, NPY_UINT32, s->corners, sizeof(uint32_t));
    PyObject *deleted = new_array(2, (npy_intp)s->num_deleted, 2, NPY_UINT32, s->deleted,
                                  sizeof(uint32_t));
    PyObject *problems = new_array(1, (npy_intp)s->num_problems, 0, NPY_UINT32, s->problems,
                                   sizeof(uint32_t));
    if (!report || !stats || !points || !kind || !degree || !first || !corners || !deleted ||
        !problems) {
        Py_XDECREF(report), Py_XDECREF(stats), Py_XDECREF(points), Py_XDECREF(kind);
        Py_XDECREF(degree), Py_XDECREF(first), Py_XDECREF(corners), Py_XDECREF(deleted);
        Py_XDECREF(problems);
        return NULL;
    }
    return Py_BuildValue("{s:N,s:N,s:N,s:N,s:N,s:N,s:N,s:N,s:N}", "points", points, "kind", kind,
                         "degree", degree, "first", first, "corners", corners, "deleted", deleted,
                         "problems", problems, "report", report, "stats", stats);
}

static PyObject *py_smooth(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *v, *o, *i, *n;
    const char *scheme;
    int estimate, split;
    if (!PyArg_ParseTuple(args, "OOOOspp", &v, &o, &i, &n, &scheme, &estimate, &split))
        return NULL;
    skpy_mesh m;
    if (parse_mesh(v, o, i, n, NULL, &m))
        return NULL;
    skpy_smooth_args a = {scheme, estimate, split};
    skpy_surface s;
    sk_error err = {0};
    sk_status st;
    Py_BEGIN_ALLOW_THREADS
    st = skpy_smooth(&m, &a, &s, &err);
    Py_END_ALLOW_THREADS
    if (st < 0)
        return raise_status(st, &err);
    PyObject *d = surface_dict(&s);
    skpy_surface_free(&s);
    return d;
}

static PyObject *py_write_surface(PyObject *self, PyObject *args)
{
    (void)self;
    PyObject *path_obj, *pts, *kind, *degree, *first, *corners;
    unsigned tess = 0;
    if (!PyArg_ParseTuple(args, "O&OOOOOI", PyUnicode_FSConverter, &path_obj, &pts, &kind,
                          &degree, &first, &corners, &tess))
        return NULL;
    skpy_surface s;
    memset(&s, 0, sizeof s);
    npy_intp np_ = 0, npts = 0;
    if (!(s.points = array_data(pts, "points", NPY_FLOAT64, 2, -1, 3, &npts)) ||
        !(s.kind = array_data(kind, "kind", NPY_UINT8, 1, -1, 0, &np_)) ||
        !(s.degree = array_data(degree, "degree", NPY_UINT8, 1, np_, 0, NULL)) ||
        !(s.first = array_data(first, "first", NPY_UINT32, 1, np_, 0, NULL)) ||
        !(s.corners = array_data(corners, "corners", NPY_UINT32, 2, np_, 4, NULL))) {
        Py_DECREF(path_obj);
        return NULL;
    }
    s.num_patches = (size_t)np_;
    s.num_points = (size_t)npts;
    sk_error err;
    sk_status st;
    Py_BEGIN_ALLOW_THREADS
    st = skpy_write_surface(PyBytes_AS_STRING(path_obj), &s, tess, &err);
    Py_END_ALLOW_THREADS
    Py_DECREF(path_obj);
    if (st < 0)
        return raise_status(st, &err);
    Py_RETURN_NONE;
}

static PyMethodDef methods[] = {
    {"read", py_read, METH_VARARGS, "read(path) -> (vertices, offsets, indices, normals, uv)"},
    {"write", py_write, METH_VARARGS, "write(path, vertices, offsets, indices, normals, uv)"},
    {"write_surface", py_write_surface, METH_VARARGS,
     "write_surface(path, points, kind, degree, first, corners, tess)"},
    {"info", py_info, METH_VARARGS, "info(vertices, offsets, indices) -> dict"},
    {"parametrize", py_parametrize, METH_VARARGS,
     "parametrize(vertices, offsets, indices, method, boundary, seed, steps) -> (uv, metrics)"},
    {"smooth", py_smooth, METH_VARARGS,
     "smooth(vertices, offsets, indices, normals, scheme, estimate_normals, allow_split) -> dict"},
    {NULL, NULL, 0, NULL},
};

static struct PyModuleDef module = {PyModuleDef_HEAD_INIT, "surfkit._core",
                                    "libsurfkit calls (use the surfkit package)", -1, methods,
                                    NULL, NULL, NULL, NULL};

PyMODINIT_FUNC PyInit__core(void); /* the import hook */

PyMODINIT_FUNC PyInit__core(void)
{
    import_array();
    PyObject *mod = PyModule_Create(&module);
    if (!mod)
        return NULL;
    sk_py_error = PyErr_NewExceptionWithDoc(
        "surfkit.Error", "A libsurfkit error: str() is its one-line message, .status its kind.",
        NULL, NULL);
    if (!sk_py_error || PyModule_AddObject(mod, "Error", sk_py_error) < 0) {
        Py_XDECREF(sk_py_error);
        Py_DECREF(mod);
        return NULL;
    }
    Py_INCREF(sk_py_error); /* the module holds one reference, this file another */
    if (PyModule_AddStringConstant(mod, "library_version", sk_version()) < 0) {
        Py_DECREF(mod);
        return NULL;
    }
    return mod;
}
