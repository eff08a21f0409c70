# Writes gmsh_periodic{22,41}[_binary].msh: the mesh of gmsh_periodic.geo with every element
# (Mesh.SaveAll: points and lines too), its $Periodic section, and a $NodeData view (with an
# $InterpolationScheme in 4.1) appended, to test the sections and element types skipped.
# Usage: python3 gmsh_periodic.py <2.2|4.1> <0|1 (binary)> <out.msh>
import sys

import gmsh

version, binary, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
gmsh.initialize()
gmsh.option.setNumber("General.Terminal", 0)
gmsh.open("gmsh_periodic.geo")
gmsh.option.setNumber("Mesh.MeshSizeMin", 1)
gmsh.option.setNumber("Mesh.MeshSizeMax", 1)
gmsh.model.mesh.generate(3)
gmsh.option.setNumber("Mesh.SaveAll", 1)
gmsh.option.setNumber("Mesh.MshFileVersion", float(version))
gmsh.option.setNumber("Mesh.Binary", binary)
gmsh.write(out)
tags, coords, _ = gmsh.model.mesh.getNodes()
view = gmsh.view.add("x")
gmsh.view.addModelData(view, 0, "", "NodeData", list(tags), [[c] for c in coords[0::3]])
gmsh.option.setNumber("PostProcessing.SaveMesh", 0)
gmsh.view.write(view, out, append=True)
gmsh.finalize()
