"""ParaView's Plot Over Line through the grid frames of column_grid.toml: sigma_yy along the
column's axis x = 0.1 m, from below the base to above the top, at the last frame.

usage: pvpython plot_over_line.py RESULTS_DIR   (writes RESULTS_DIR/stress_over_line.csv)
       (xvfb-run -a pvpython ... on a machine without a display)

It opens the run as particles_view.py does (the particles, and grid.pvd beside them, not shown),
then applies Plot Over Line to grid.pvd, as one would in the GUI: select grid.pvd in the Pipeline
Browser, Filters > Data Analysis > Plot Over Line. Columns of the CSV: y (m), sigma_yy (Pa, tension
positive), valid (ParaView's vtkValidPointMask: 0 where the line leaves the cells, that is the
nodes with mass, so above the column there is no value rather than a stress of 0), and the
reference -rho g (H - y).
"""
import os
import sys

from paraview import servermanager
from paraview.simple import FindSource, GetAnimationScene, PlotOverLine

RHO_G, H = 2000.0 * 9.81, 1.0  # as in column.toml

results = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else "results")
view_script = os.path.join(results, "particles_view.py")
exec(compile(open(view_script).read(), view_script, "exec"), {"__file__": view_script, "__name__": "__main__"})

line = PlotOverLine(Input=FindSource("grid.pvd"))
line.Point1 = [0.1, -0.1, 0.0]
line.Point2 = [0.1, 1.3, 0.0]
line.SamplingPattern = "Sample Uniformly"
line.Resolution = 28  # every 0.05 m: the nodes of the line and the points between them
line.UpdatePipeline(GetAnimationScene().AnimationTime)
data = servermanager.Fetch(line)
stress = data.GetPointData().GetArray("stress")
valid = data.GetPointData().GetArray("vtkValidPointMask")
with open(os.path.join(results, "stress_over_line.csv"), "w") as f:
    f.write("y,sigma_yy,valid,reference\n")
    for k in range(data.GetNumberOfPoints()):
        y = data.GetPoint(k)[1]
        f.write(f"{y:.9g},{stress.GetComponent(k, 1):.9g},{int(valid.GetTuple1(k))},{-RHO_G * (H - y):.9g}\n")
print("wrote", os.path.join(results, "stress_over_line.csv"))
