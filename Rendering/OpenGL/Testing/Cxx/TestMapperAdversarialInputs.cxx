// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The adversarial suite of the mappers (vtkPreIntegrationVolumeMapper in both orders,
// vtkAnalyticVolumeMapper for isosurfaces and maxima, vtkObjectOrderVolumeMapper) and of the
// OpenGL helpers (vtkFloatRGBARenderCapture, vtkOpenGLPreIntegrationTableBuilder): truncated
// and long arrays, non-finite geometry, NaN, Inf and fill values, 1-voxel slabs, careless sample
// distances and every scalar type must each end in a drawn, finite image or in an error
// through the mapper's observers with nothing drawn; never a crash, a sanitizer report, or an
// empty image without a message. Prints a table of case -> outcome.
#include "hovrRenderTestUtilities.h"

#include "vtkAnalyticVolumeMapper.h"
#include "vtkContourValues.h"
#include "vtkFloatRGBARenderCapture.h"
#include "vtkObjectOrderVolumeMapper.h"
#include "vtkOpenGLPreIntegrationTableBuilder.h"
#include "vtkOpenGLRenderWindow.h"
#include "vtkPreIntegrationVolumeMapper.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkTextureObject.h"
#include "vtkVolume.h"

#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace
{
const int Size = 48;
const double NaN = std::numeric_limits<double>::quiet_NaN();

enum Expect
{
  IMAGE,
  ERROR,
  EITHER
};

struct Row
{
  std::string Case, Mapper, Outcome;
  bool Ok;
};

// The mappers under test, each a fresh instance on every case.
const char* MapperNames[] = { "preint1", "preint2", "iso-analytic", "mip-analytic", "objectorder" };
const int Mappers = 5;

vtkSmartPointer<vtkAbstractVolumeMapper> MakeMapper(int which, double step)
{
  if (which <= 1)
  {
    auto mapper = vtkSmartPointer<vtkPreIntegrationVolumeMapper>::New();
    mapper->SetIntegration(which == 0 ? vtkPreIntegrationVolumeMapper::FIRST_ORDER
                                      : vtkPreIntegrationVolumeMapper::SECOND_ORDER);
    mapper->SetSampleDistance(step);
    return mapper;
  }
  if (which <= 3)
  {
    auto mapper = vtkSmartPointer<vtkAnalyticVolumeMapper>::New();
    mapper->SetBlendMode(
      which == 2 ? vtkVolumeMapper::ISOSURFACE_BLEND : vtkVolumeMapper::MAXIMUM_INTENSITY_BLEND);
    return mapper;
  }
  auto mapper = vtkSmartPointer<vtkObjectOrderVolumeMapper>::New();
  mapper->SetSampleDistance(step);
  return mapper;
}

// A copy of image whose scalar array has n values (repeating the first ones).
vtkSmartPointer<vtkImageData> WithValues(vtkImageData* image, vtkIdType n)
{
  auto copy = vtkSmartPointer<vtkImageData>::New();
  copy->CopyStructure(image);
  vtkDataArray* in = image->GetPointData()->GetScalars();
  vtkSmartPointer<vtkDataArray> out;
  out.TakeReference(in->NewInstance());
  out->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    out->SetComponent(i, 0, in->GetComponent(i % in->GetNumberOfTuples(), 0));
  }
  copy->GetPointData()->SetScalars(out);
  return copy;
}

// A copy of image with f applied to every value.
vtkSmartPointer<vtkImageData> Mapped(vtkImageData* image, const std::function<double(double)>& f)
{
  auto copy = hovrTest::ConvertScalars(image, VTK_DOUBLE, 1.0, 0.0);
  vtkDataArray* values = copy->GetPointData()->GetScalars();
  for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
  {
    values->SetComponent(i, 0, f(values->GetComponent(i, 0)));
  }
  return copy;
}
}

int TestMapperAdversarialInputs(int, char*[])
{
  hovrTest::Checker check;
  hovrTest::FloatRenderView view;
  if (!check(view.Initialize(Size, Size), "float capture attached"))
  {
    return check.Result("TestMapperAdversarialInputs");
  }
  vtkNew<vtkVolume> volume;
  view.GetRenderer()->AddVolume(volume);
  auto property = hovrTest::MakeSpikeProperty(0.0, 1.0);
  property->GetIsoSurfaceValues()->SetValue(0, 0.5);
  volume->SetProperty(property);
  auto base = hovrTest::MakeMarschnerLobb(17);
  const double bounds[6] = { -1, 1, -1, 1, -1, 1 };
  std::vector<Row> table;

  auto run = [&](const std::string& name,
               vtkImageData* data,
               Expect expect,
               std::vector<int> mappers = { 0, 1, 2, 3, 4 },
               double step = 0.05)
  {
    for (int which : mappers)
    {
      vtkNew<vtkTest::ErrorObserver> said;
      auto mapper = MakeMapper(which, step);
      hovrTest::Observe(mapper, said);
      mapper->SetInputDataObject(data);
      volume->SetMapper(mapper);
      hovrTest::SetObliqueCamera(view.GetCamera(), bounds);
      // Object-order ray casting needs a parallel projection (it falls back otherwise).
      view.GetCamera()->SetParallelProjection(which == 4);
      view.GetCamera()->SetParallelScale(1.8);
      auto image = view.Render();
      const bool error = said->GetError();
      const bool warned = said->GetWarning();
      const double drawn = image ? hovrTest::MaximumValue(image) : 0.0;
      const bool finite = image && hovrTest::AllFinite(image);
      bool ok = image && finite;
      if (error)
      {
        ok = ok && expect != IMAGE && drawn == 0.0;
      }
      else
      {
        ok = ok && expect != ERROR && (drawn > 0.0 || warned);
      }
      std::string message = error ? said->GetErrorMessage() : said->GetWarningMessage();
      const size_t at = message.find("): ");
      message = at == std::string::npos ? message : message.substr(at + 3);
      message = message.substr(0, std::min<size_t>(message.find('\n'), 90));
      char outcome[200];
      std::snprintf(outcome,
        sizeof(outcome),
        "%s%s%s",
        error ? "error: " : "",
        error ? message.c_str() : (drawn > 0.0 ? "drawn" : "empty"),
        !error && warned ? (" (warned: " + message + ")").c_str() : "");
      table.push_back({ name, MapperNames[which], outcome, ok });
      check(ok, name + " / " + MapperNames[which] + ": " + outcome);
      volume->SetMapper(nullptr);
    }
  };

  run("Marschner-Lobb 17^3", base, IMAGE);
  run("100 values for 17^3 points", WithValues(base, 100), ERROR);
  run("10000 values for 17^3 points", WithValues(base, 10000), ERROR);
  {
    auto copy = WithValues(base, base->GetNumberOfPoints());
    copy->SetOrigin(NaN, 0, 0);
    run("NaN origin", copy, ERROR);
    copy = WithValues(base, base->GetNumberOfPoints());
    copy->SetSpacing(0.125, 0.0, 0.125);
    run("zero spacing", copy, ERROR);
  }
  run("some Inf", Mapped(base, [](double v) { return v > 0.9 ? HUGE_VAL : v; }), ERROR);
  run("all NaN", Mapped(base, [](double) { return NaN; }), EITHER);
  run("some NaN", Mapped(base, [](double v) { return v > 0.9 ? NaN : v; }), IMAGE);
  run("constant 1e20", Mapped(base, [](double) { return 1e20; }), EITHER);
  run("constant 0.5", Mapped(base, [](double) { return 0.5; }), EITHER);
  {
    vtkNew<vtkImageData> slab;
    slab->SetDimensions(8, 8, 1);
    slab->SetSpacing(0.25, 0.25, 0.25);
    slab->SetOrigin(-1, -1, 0);
    slab->AllocateScalars(VTK_FLOAT, 1);
    slab->GetPointData()->GetScalars()->Fill(0.5);
    run("slab 8x8x1", slab, ERROR);
  }
  for (double step : { 0.0, -1.0, NaN, 1e-9 })
  {
    char name[64];
    std::snprintf(name, sizeof(name), "step %g", step);
    run(name, base, ERROR, { 0, 1, 4 }, step);
  }
  for (int type : { VTK_CHAR,
         VTK_UNSIGNED_CHAR,
         VTK_SHORT,
         VTK_UNSIGNED_SHORT,
         VTK_INT,
         VTK_UNSIGNED_INT,
         VTK_LONG_LONG,
         VTK_DOUBLE })
  {
    auto typed =
      hovrTest::ConvertScalars(Mapped(base, [](double v) { return 100.0 * v; }), type, 1.0, 0.0);
    vtkSmartPointer<vtkDataArray> a;
    a.TakeReference(vtkDataArray::CreateDataArray(type));
    auto wide = hovrTest::MakeSpikeProperty(0.0, 100.0);
    wide->GetIsoSurfaceValues()->SetValue(0, 50.0);
    volume->SetProperty(wide);
    // VTK's GPU ray caster refuses char, whose signedness depends on the platform.
    run(std::string("scalar type ") + a->GetDataTypeAsString(),
      typed,
      type == VTK_CHAR ? EITHER : IMAGE);
    volume->SetProperty(property);
  }

  {
    // The OpenGL helpers: each misuse is an error through their observers.
    auto expectError = [&](const std::string& name,
                         const char* helper,
                         vtkObject* object,
                         const std::function<bool()>& call)
    {
      vtkNew<vtkTest::ErrorObserver> said;
      hovrTest::Observe(object, said);
      const bool ok = !call() && said->GetError();
      table.push_back({ name, helper, ok ? "error" : "no error", ok });
      check(ok, name + " / " + helper + ": an error");
      object->RemoveAllObservers();
    };
    vtkNew<vtkFloatRGBARenderCapture> capture;
    vtkNew<vtkImageData> image;
    expectError(
      "capture before Attach", "float capture", capture, [&] { return capture->Capture(image); });
    expectError(
      "Attach to no window", "float capture", capture, [&] { return capture->Attach(nullptr); });
    vtkNew<vtkOpenGLPreIntegrationTableBuilder> builder;
    vtkNew<vtkSecondOrderPreIntegrationTable> unbuilt;
    vtkNew<vtkTextureObject> texture;
    auto* context = vtkOpenGLRenderWindow::SafeDownCast(view.GetWindow());
    const unsigned int rgba32f = 0x8814; // GL_RGBA32F
    expectError("build without a context",
      "table builder",
      builder,
      [&] { return builder->Build(nullptr, unbuilt, texture, rgba32f); });
    expectError("build of an unprepared table",
      "table builder",
      builder,
      [&] { return builder->Build(context, unbuilt, texture, rgba32f); });
    expectError("build into format 0x1234",
      "table builder",
      builder,
      [&] { return builder->Build(context, unbuilt, texture, 0x1234); });
  }

  std::printf("%-28s  %-13s  %s\n", "case", "mapper", "outcome");
  for (const Row& row : table)
  {
    std::printf("%-28s  %-13s  %s%s\n",
      row.Case.c_str(),
      row.Mapper.c_str(),
      row.Ok ? "" : "FAILED: ",
      row.Outcome.c_str());
  }
  return check.Result("TestMapperAdversarialInputs");
}
