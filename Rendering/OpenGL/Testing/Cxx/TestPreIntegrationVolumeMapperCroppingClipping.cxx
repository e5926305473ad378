// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Proves that first-order pre-integration honours VTK's cropping regions, clipping planes (on
// the near and the far side of the rays), opaque geometry inside the volume and ray
// jittering: under each, its image stays close to VTK's stock compositing at a fine step
// with the same cropping, clipping or jittering (so segments start, stop and skip where VTK's
// ray does), while the cropped or clipped image clearly differs from the uncropped one (so
// the cut really happened) and the jittered one differs from the unjittered one.
//
// VTK 9.1's shader compares cropping and clipping planes with sample positions in texture
// coordinates of two kinds (box-normalised planes against texel-centred positions), which
// moves its cuts away from the box's centre by 1/(N - 1) of their distance from it (N points
// per axis; up to half a voxel at the faces). The mapper under test cuts at the planes
// themselves; stock gets its planes moved in by as much, so that both cut in one place.
#include "hovrRenderTestUtilities.h"

#include "vtkActor.h"
#include "vtkCellArray.h"
#include "vtkOpenGLGPUVolumeRayCastMapper.h"
#include "vtkPlane.h"
#include "vtkPlaneCollection.h"
#include "vtkPoints.h"
#include "vtkPolyData.h"
#include "vtkPolyDataMapper.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkProperty.h"
#include "vtkVolume.h"

#include <functional>
#include <iostream>

int TestPreIntegrationVolumeMapperCroppingClipping(int, char*[])
{
  hovrTest::Checker check;
  const int size = 128;
  auto data = hovrTest::MakeMarschnerLobb(41, VTK_FLOAT);
  auto property = hovrTest::MakeSpikeProperty();
  const double voxel = data->GetSpacing()[0];

  hovrTest::FloatRenderView view;
  if (!check(view.Initialize(size, size), "float colour buffer attached"))
  {
    return check.Result("TestPreIntegrationVolumeMapperCroppingClipping");
  }
  hovrTest::SetObliqueCamera(view.GetCamera(), data->GetBounds());

  vtkNew<vtkPreIntegrationVolumeMapper> preint;
  preint->SetInputData(data);
  vtkNew<vtkOpenGLGPUVolumeRayCastMapper> stock;
  stock->SetInputData(data);
  stock->SetAutoAdjustSampleDistances(0);
  stock->SetSampleDistance(0.0625 * voxel);
  vtkNew<vtkTest::ErrorObserver> errors;
  hovrTest::Observe(preint, errors);
  hovrTest::Observe(stock, errors);
  vtkNew<vtkVolume> volume;
  volume->SetProperty(property);
  view.GetRenderer()->AddVolume(volume);

  auto render = [&](vtkVolumeMapper* mapper)
  {
    volume->SetMapper(mapper);
    return view.Render();
  };
  auto plainStock = render(stock);

  // Where stock must be told to cut so that it cuts at x along axis a (see above).
  const int* dims = data->GetDimensions();
  const double* dataBounds = data->GetBounds();
  auto stockCut = [&](double x, int a)
  {
    const double centre = 0.5 * (dataBounds[2 * a] + dataBounds[2 * a + 1]);
    return centre + (x - centre) * (dims[a] - 1.0) / dims[a];
  };
  auto makePlanes = [&](double sign, bool forStock)
  {
    const double origin[3] = { 0.1, 0.0, 0.2 };
    vtkNew<vtkPlane> plane;
    plane->SetOrigin(forStock ? stockCut(origin[0], 0) : origin[0],
      forStock ? stockCut(origin[1], 1) : origin[1],
      forStock ? stockCut(origin[2], 2) : origin[2]);
    plane->SetNormal(-0.8 * sign, 0.5 * sign, -0.3 * sign);
    vtkNew<vtkPlaneCollection> planes;
    planes->AddItem(plane);
    return vtkSmartPointer<vtkPlaneCollection>(planes);
  };
  auto planes = makePlanes(1.0, false), stockPlanes = makePlanes(1.0, true);
  // The opposite half: this plane ends the rays instead of starting them.
  auto farPlanes = makePlanes(-1.0, false), stockFarPlanes = makePlanes(-1.0, true);
  auto setCropping = [&](vtkVolumeMapper* m)
  {
    const double planes[6] = { -0.55, 0.45, -0.65, 0.35, -0.75, 0.6 };
    double moved[6];
    for (int i = 0; i < 6; ++i)
    {
      moved[i] = m == stock.Get() ? stockCut(planes[i], i / 2) : planes[i];
    }
    m->CroppingOn();
    m->SetCroppingRegionPlanes(moved);
  };

  // An opaque black floor at z = -0.2 through the volume: rays stop at its depth.
  vtkNew<vtkPoints> corners;
  corners->InsertNextPoint(-1.5, -1.5, -0.2);
  corners->InsertNextPoint(1.5, -1.5, -0.2);
  corners->InsertNextPoint(1.5, 1.5, -0.2);
  corners->InsertNextPoint(-1.5, 1.5, -0.2);
  vtkNew<vtkCellArray> quadCell;
  const vtkIdType quadIds[4] = { 0, 1, 2, 3 };
  quadCell->InsertNextCell(4, quadIds);
  vtkNew<vtkPolyData> quad;
  quad->SetPoints(corners);
  quad->SetPolys(quadCell);
  vtkNew<vtkPolyDataMapper> quadMapper;
  quadMapper->SetInputData(quad);
  vtkNew<vtkActor> floor;
  floor->SetMapper(quadMapper);
  floor->GetProperty()->LightingOff();
  floor->GetProperty()->SetColor(0.0, 0.0, 0.0);
  auto setJittering = [](vtkVolumeMapper* m, int on)
  { vtkGPUVolumeRayCastMapper::SafeDownCast(m)->SetUseJittering(on); };

  // Bounds are RMSE of preint against stock at 1/16 voxel, above the error without a cut. A crop
  // boundary inside the volume costs up to one segment per crossing (the skip flag applies to
  // whole segments, as to whole samples in VTK); clipping planes and the depth of opaque
  // geometry cut segments exactly.
  // Jittering is tested at 1 voxel, where it visibly changes the image; it must not make the
  // error worse than without it.
  struct Case
  {
    const char* Name;
    double Step;       // preint sample distance in voxels
    double Bound;      // RMSE bound vs stock at 1/16 voxel
    double MinimumCut; // RMSE the cut must change the preint image by
    std::function<void(vtkVolumeMapper*)> Apply;
    std::function<void(vtkVolumeMapper*)> Undo;
  };
  const Case cases[] = {
    { "cropping (sub-volume)",
      0.25,
      0.009,
      0.1,
      [&](vtkVolumeMapper* m)
      {
        setCropping(m);
        m->SetCroppingRegionFlagsToSubVolume();
      },
      [](vtkVolumeMapper* m) { m->CroppingOff(); } },
    { "cropping (inverted cross)",
      0.25,
      0.013,
      0.1,
      [&](vtkVolumeMapper* m)
      {
        setCropping(m);
        m->SetCroppingRegionFlagsToInvertedCross();
      },
      [](vtkVolumeMapper* m) { m->CroppingOff(); } },
    { "clipping plane",
      0.25,
      0.010,
      0.1,
      [&](vtkVolumeMapper* m) { m->SetClippingPlanes(m == stock.Get() ? stockPlanes : planes); },
      [](vtkVolumeMapper* m) { m->SetClippingPlanes(static_cast<vtkPlaneCollection*>(nullptr)); } },
    { "clipping plane (far side)",
      0.25,
      0.009,
      0.1,
      [&](vtkVolumeMapper* m)
      { m->SetClippingPlanes(m == stock.Get() ? stockFarPlanes : farPlanes); },
      [](vtkVolumeMapper* m) { m->SetClippingPlanes(static_cast<vtkPlaneCollection*>(nullptr)); } },
    { "opaque polygon inside the volume",
      0.25,
      0.006,
      0.1,
      [&](vtkVolumeMapper*)
      {
        if (!view.GetRenderer()->HasViewProp(floor))
        {
          view.GetRenderer()->AddActor(floor);
        }
      },
      [&](vtkVolumeMapper*) { view.GetRenderer()->RemoveActor(floor); } },
    { "jittering",
      1.0,
      0.045,
      0.01,
      [&](vtkVolumeMapper* m) { setJittering(m, 1); },
      [&](vtkVolumeMapper* m) { setJittering(m, 0); } },
  };
  for (const Case& c : cases)
  {
    const std::string name = c.Name;
    preint->SetSampleDistance(c.Step * voxel);
    auto plainPreint = render(preint);
    c.Apply(preint);
    c.Apply(stock);
    auto cutPreint = render(preint);
    auto cutStock = render(stock);
    c.Undo(preint);
    c.Undo(stock);
    const double plainRMSE = hovrTest::RMSE(plainPreint, plainStock);
    const double rmse = hovrTest::RMSE(cutPreint, cutStock);
    const double change = hovrTest::RMSE(cutPreint, plainPreint);
    std::cout << name << ", step " << c.Step << " voxel: preint vs stock RMSE " << rmse
              << " (uncut " << plainRMSE << "), change from the uncut image " << change
              << ", covered pixels " << hovrTest::CountCovered(cutPreint) << " (uncut "
              << hovrTest::CountCovered(plainPreint) << ")\n";
    check(rmse >= 0.0 && rmse < c.Bound, name + ": close to stock at a fine step");
    check(change > c.MinimumCut, name + ": differs from the uncut image");
    check(hovrTest::AllFinite(cutPreint), name + ": finite");
  }
  // The cuts are undone: the uncut image again.
  preint->SetSampleDistance(0.25 * voxel);
  auto uncut = render(preint);
  check(hovrTest::CountCovered(uncut) > size * size / 4, "uncut volume drawn again");
  hovrTest::ExpectQuiet(check, errors, "the whole test");
  return check.Result("TestPreIntegrationVolumeMapperCroppingClipping");
}
