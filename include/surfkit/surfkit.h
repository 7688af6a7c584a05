/* surfkit: hierarchical parametrization and VC1 smooth surfaces of triangulated surfaces.
 * This header includes every public module header. */
#ifndef SURFKIT_H
#define SURFKIT_H

#include "surfkit/core.h"
#include "surfkit/mesh.h"
#include "surfkit/io.h"
#include "surfkit/subdivide.h"
#include "surfkit/analysis.h"
#include "surfkit/smooth.h"
#include "surfkit/hierarchy.h"
#include "surfkit/solve.h"
#include "surfkit/param.h"
#include "surfkit/render.h"
#include "surfkit/mips.h"
#include "surfkit/hierarchical.h"
#include "surfkit/parametrize.h"
#include "surfkit/atlas.h"
#include "surfkit/bezier.h"
#include "surfkit/export.h"
#include "surfkit/deviation.h"
#include "surfkit/view.h"
#include "surfkit/intersect.h"
#include "surfkit/bspline.h"
#include "surfkit/fit.h"
#include "surfkit/tolerance.h"
#include "surfkit/bspline_export.h"

#endif
