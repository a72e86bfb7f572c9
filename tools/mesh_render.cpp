#include <meshless_tools/mesh_render.h>

#include <pcl/io/vtk_lib_io.h>

#include <vtkActor.h>
#include <vtkAutoInit.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkPNGWriter.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkSmartPointer.h>
#include <vtkWindowToImageFilter.h>

// The OpenGL back end registers itself through this static object; off-screen
// rendering finds no render window implementation without it.
VTK_MODULE_INIT (vtkRenderingOpenGL2);

namespace meshless_tools {

namespace {

vtkSmartPointer<vtkActor>
lineActor (const LineSet& set)
{
  auto points = vtkSmartPointer<vtkPoints>::New ();
  auto lines = vtkSmartPointer<vtkCellArray>::New ();
  for (const auto& segment : set.segments) {
    const vtkIdType a = points->InsertNextPoint (segment[0].data ());
    const vtkIdType b = points->InsertNextPoint (segment[1].data ());
    const vtkIdType ids[2] = {a, b};
    lines->InsertNextCell (2, ids);
  }
  auto data = vtkSmartPointer<vtkPolyData>::New ();
  data->SetPoints (points);
  data->SetLines (lines);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New ();
  mapper->SetInputData (data);
  auto actor = vtkSmartPointer<vtkActor>::New ();
  actor->SetMapper (mapper);
  actor->GetProperty ()->SetColor (set.colour[0], set.colour[1], set.colour[2]);
  actor->GetProperty ()->SetLineWidth (static_cast<float> (set.width));
  actor->GetProperty ()->LightingOff ();
  return actor;
}

} // namespace

std::string
renderPng (const pcl::PolygonMesh& mesh, const std::array<double, 6>& bounds,
           const std::string& path, const RenderOptions& options)
{
  vtkSmartPointer<vtkPolyData> poly_data;
  pcl::io::mesh2vtk (mesh, poly_data);
  auto mapper = vtkSmartPointer<vtkPolyDataMapper>::New ();
  mapper->SetInputData (poly_data);
  mapper->ScalarVisibilityOff ();
  auto actor = vtkSmartPointer<vtkActor>::New ();
  actor->SetMapper (mapper);
  // Both sides alike (VTK lights both): the picture shows the surface, not its
  // orientation, which the tools report in their tables.
  actor->GetProperty ()->SetColor (0.85, 0.85, 0.80);
  if (options.draw_edges) {
    actor->GetProperty ()->EdgeVisibilityOn ();
    actor->GetProperty ()->SetEdgeColor (0.25, 0.25, 0.3);
    actor->GetProperty ()->SetLineWidth (1.0f);
  }

  auto renderer = vtkSmartPointer<vtkRenderer>::New ();
  renderer->AddActor (actor);
  for (const LineSet& set : options.lines)
    if (!set.segments.empty ())
      renderer->AddActor (lineActor (set));
  renderer->SetBackground (1.0, 1.0, 1.0);
  vtkCamera* camera = renderer->GetActiveCamera ();
  camera->SetFocalPoint (0.0, 0.0, 0.0);
  camera->SetPosition (options.view[0], options.view[1], options.view[2]);
  camera->SetViewUp (0.0, 1.0, 0.0);
  double box[6];
  std::copy (bounds.begin (), bounds.end (), box);
  renderer->ResetCamera (box);

  auto window = vtkSmartPointer<vtkRenderWindow>::New ();
  window->SetOffScreenRendering (1);
  window->SetSize (options.size, options.size);
  window->AddRenderer (renderer);
  window->Render ();
  auto image = vtkSmartPointer<vtkWindowToImageFilter>::New ();
  image->SetInput (window);
  image->Update ();
  auto writer = vtkSmartPointer<vtkPNGWriter>::New ();
  writer->SetFileName (path.c_str ());
  writer->SetInputConnection (image->GetOutputPort ());
  writer->Write ();
  return writer->GetErrorCode () == 0 ? "" : "cannot write " + path;
}

} // namespace meshless_tools
