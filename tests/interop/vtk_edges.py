"""Boundary and non-manifold edge counts of a mesh file by VTK (vtkFeatureEdges), on the file's
own connectivity (no point merging). Usage: vtk_edges.py FILE.{ply,obj,stl}; prints JSON."""
import json
import sys

import vtk

path = sys.argv[1]
reader = {"ply": vtk.vtkPLYReader, "obj": vtk.vtkOBJReader, "stl": vtk.vtkSTLReader}[
    path.rsplit(".", 1)[1].lower()]()
reader.SetFileName(path)
reader.Update()
mesh = reader.GetOutput()


def edges(boundary, non_manifold):
    fe = vtk.vtkFeatureEdges()
    fe.SetInputData(mesh)
    fe.FeatureEdgesOff()
    fe.ManifoldEdgesOff()
    fe.SetBoundaryEdges(boundary)
    fe.SetNonManifoldEdges(non_manifold)
    fe.Update()
    return fe.GetOutput().GetNumberOfCells()


conn = vtk.vtkPolyDataConnectivityFilter()
conn.SetInputData(mesh)
conn.SetExtractionModeToAllRegions()
conn.Update()
print(json.dumps({"points": mesh.GetNumberOfPoints(), "cells": mesh.GetNumberOfCells(),
                  "boundary_edges": edges(True, False), "non_manifold_edges": edges(False, True),
                  "regions": conn.GetNumberOfExtractedRegions()}))
