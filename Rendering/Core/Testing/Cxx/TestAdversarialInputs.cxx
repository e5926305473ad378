// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// The adversarial suite of the GL-free classes. Scientists' files and careless settings give
// truncated arrays, fill values, NaN and Inf, extreme spacings, steps and cameras, degenerate
// transfer functions and volumes changed in place; each case must end, within a time bound, in
// a correct image (checked against the reference integrator) or in an error reported through
// the class's observers. An empty image without a message fails, as does a crash, a sanitizer
// report or a hang (ctest's timeout). Prints a table of case -> outcome.
// One file, beyond the usual length: the cases share one harness and print one table.
#include "vtkCallbackCommand.h"
#include "vtkCamera.h"
#include "vtkCameraRayModel.h"
#include "vtkColorTransferFunction.h"
#include "vtkDataArray.h"
#include "vtkFirstOrderPreIntegrationTable.h"
#include "vtkFloatArray.h"
#include "vtkGridRayTraversal.h"
#include "vtkHierarchicalOcclusionMap.h"
#include "vtkImageData.h"
#include "vtkMatrix3x3.h"
#include "vtkMatrix4x4.h"
#include "vtkMinMaxOctree.h"
#include "vtkNew.h"
#include "vtkObjectOrderRayCaster.h"
#include "vtkPiecewiseFunction.h"
#include "vtkPointData.h"
#include "vtkPreIntegrationRayCaster.h"
#include "vtkPreIntegrationTableSizer.h"
#include "vtkRGBAErrorMetrics.h"
#include "vtkSecondOrderPreIntegrationTable.h"
#include "vtkSmartPointer.h"
#include "vtkTrilinearRayProfile.h"
#include "vtkVolumeProperty.h"
#include "vtkVolumeReferenceIntegrator.h"
#include "vtkVolumeTransferFunctionSampler.h"

#include "hovrTestUtilities.h"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace
{
hovrTest::Checker check;
const double Inf = std::numeric_limits<double>::infinity();
const double NaN = std::numeric_limits<double>::quiet_NaN();
// Seconds a case may take in a sanitized build on a loaded machine.
const double TimeBound = 60.0;
const int ImageSide = 20;

// Errors and warnings an object reported through its observers.
struct Messages
{
  int Errors = 0;
  int Warnings = 0;
  std::string Text;
};

void Listen(vtkObject* object, Messages* messages)
{
  vtkNew<vtkCallbackCommand> command;
  command->SetClientData(messages);
  command->SetCallback(
    [](vtkObject*, unsigned long event, void* client, void* data)
    {
      auto* m = static_cast<Messages*>(client);
      (event == vtkCommand::ErrorEvent ? m->Errors : m->Warnings)++;
      if (data && m->Text.size() < 400)
      {
        m->Text += static_cast<const char*>(data);
      }
    });
  object->AddObserver(vtkCommand::ErrorEvent, command);
  object->AddObserver(vtkCommand::WarningEvent, command);
}

// What an image algorithm produced.
struct Outcome
{
  Messages Said;
  vtkSmartPointer<vtkImageData> Image;
  double MaxAlpha = 0.0;
  bool Finite = true;
  double Seconds = 0.0;
};

Outcome Run(vtkAlgorithm* algorithm)
{
  Outcome out;
  Listen(algorithm, &out.Said);
  const auto start = std::chrono::steady_clock::now();
  algorithm->Update();
  out.Seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.Image = vtkImageData::SafeDownCast(algorithm->GetOutputDataObject(0));
  vtkDataArray* rgba = out.Image ? out.Image->GetPointData()->GetArray("RGBA") : nullptr;
  for (vtkIdType i = 0; rgba && i < rgba->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 4; ++c)
    {
      out.Finite = out.Finite && std::isfinite(rgba->GetComponent(i, c));
    }
    out.MaxAlpha = std::max(out.MaxAlpha, rgba->GetComponent(i, 3));
  }
  algorithm->RemoveAllObservers();
  return out;
}

// RMSE of premultiplied RGBA between two images of the same size (infinity otherwise).
double Difference(vtkImageData* a, vtkImageData* b)
{
  vtkDataArray* x = a ? a->GetPointData()->GetArray("RGBA") : nullptr;
  vtkDataArray* y = b ? b->GetPointData()->GetArray("RGBA") : nullptr;
  if (!x || !y || x->GetNumberOfTuples() != y->GetNumberOfTuples())
  {
    return Inf;
  }
  double sum = 0.0;
  for (vtkIdType i = 0; i < x->GetNumberOfTuples(); ++i)
  {
    for (int c = 0; c < 4; ++c)
    {
      const double d = x->GetComponent(i, c) - y->GetComponent(i, c);
      sum += d * d;
    }
  }
  return std::sqrt(sum / (4.0 * std::max<vtkIdType>(x->GetNumberOfTuples(), 1)));
}

// A volume of dims points whose scalar at point (i, j, k) is f(u, v, w), u = i / (dims - 1).
vtkSmartPointer<vtkImageData> Volume(const std::array<int, 3>& dims,
  const std::function<double(double, double, double)>& f,
  int type = VTK_FLOAT,
  double spacing = 1.0)
{
  auto image = vtkSmartPointer<vtkImageData>::New();
  image->SetDimensions(dims.data());
  image->SetSpacing(spacing, spacing, spacing);
  vtkSmartPointer<vtkDataArray> values;
  values.TakeReference(vtkDataArray::CreateDataArray(type));
  values->SetName("scalars");
  values->SetNumberOfTuples(image->GetNumberOfPoints());
  vtkIdType n = 0;
  for (int k = 0; k < dims[2]; ++k)
  {
    for (int j = 0; j < dims[1]; ++j)
    {
      for (int i = 0; i < dims[0]; ++i)
      {
        auto at = [](int x, int d) { return d > 1 ? x / (d - 1.0) : 0.0; };
        values->SetComponent(n++, 0, f(at(i, dims[0]), at(j, dims[1]), at(k, dims[2])));
      }
    }
  }
  image->GetPointData()->SetScalars(values);
  return image;
}

// A smooth field in [0, 1] with a blob in the middle: rays meet transparent and opaque parts.
double Blob(double u, double v, double w)
{
  const double r2 = (u - 0.5) * (u - 0.5) + (v - 0.45) * (v - 0.45) + (w - 0.55) * (w - 0.55);
  return std::exp(-6.0 * r2);
}

vtkSmartPointer<vtkImageData> Blobs(int type = VTK_FLOAT, double spacing = 1.0, int n = 12)
{
  return Volume({ n, n, n }, Blob, type, spacing);
}

// A transfer function over [lo, hi]: transparent at lo, a ramp to 0.8 at hi, colour ramps.
vtkSmartPointer<vtkVolumeProperty> Property(double lo = 0.0, double hi = 1.0, double unit = 1.0)
{
  auto property = vtkSmartPointer<vtkVolumeProperty>::New();
  vtkNew<vtkColorTransferFunction> color;
  color->AddRGBPoint(lo, 0.2, 0.3, 1.0);
  color->AddRGBPoint(hi, 1.0, 0.8, 0.2);
  vtkNew<vtkPiecewiseFunction> opacity;
  opacity->AddPoint(lo, 0.0);
  opacity->AddPoint(lo + 0.4 * (hi - lo), 0.05);
  opacity->AddPoint(hi, 0.8);
  property->SetColor(color);
  property->SetScalarOpacity(opacity);
  property->SetScalarOpacityUnitDistance(unit);
  return property;
}

// A parallel camera that frames the volume's bounds from an oblique direction.
vtkSmartPointer<vtkCamera> Camera(vtkImageData* volume)
{
  auto camera = vtkSmartPointer<vtkCamera>::New();
  double b[6];
  volume->GetBounds(b);
  const double c[3] = { 0.5 * (b[0] + b[1]), 0.5 * (b[2] + b[3]), 0.5 * (b[4] + b[5]) };
  const double r = 0.5 *
    std::sqrt((b[1] - b[0]) * (b[1] - b[0]) + (b[3] - b[2]) * (b[3] - b[2]) +
      (b[5] - b[4]) * (b[5] - b[4]));
  camera->SetFocalPoint(c);
  camera->SetPosition(c[0] + 2.0 * r * 0.48, c[1] + 2.0 * r * 0.6, c[2] + 2.0 * r * 0.64);
  camera->SetViewUp(0, 0, 1);
  camera->ParallelProjectionOn();
  camera->SetParallelScale(std::isfinite(r) && r > 0.0 ? 1.05 * r : 1.0);
  camera->SetClippingRange(1e-3 * r, 4.0 * r);
  return camera;
}

// The image algorithms the suite drives, each with its sample distance in voxels.
enum Method
{
  REFERENCE,
  OBJECT_ORDER,
  OBJECT_ORDER_POINT,
  TWIN_FIRST,
  TWIN_SECOND,
  METHODS
};
const char* MethodNames[METHODS] = { "reference",
  "objectorder",
  "objectorder-point",
  "twin-1",
  "twin-2" };
// How far each method may be from the reference, in RGBA RMSE, on these small volumes and
// steps of a quarter voxel: their sampling and table errors are a few thousandths.
const double MethodTolerance[METHODS] = { 1e-5, 0.03, 0.03, 0.03, 0.03 };

struct Setup
{
  vtkSmartPointer<vtkImageData> Input;
  vtkSmartPointer<vtkVolumeProperty> Property;
  vtkSmartPointer<vtkCamera> Camera;
  int Width = ImageSide, Height = ImageSide;
  bool DefaultStep = true; // a quarter of the smallest spacing
  double Step = 0.0;       // world units, when not DefaultStep
  std::function<void(vtkVolumeImageAlgorithm*)> Adjust;
};

vtkSmartPointer<vtkVolumeImageAlgorithm> Make(Method method, const Setup& setup)
{
  double step = setup.Step;
  if (setup.DefaultStep && setup.Input)
  {
    const double* s = setup.Input->GetSpacing();
    step = 0.25 * std::min({ std::abs(s[0]), std::abs(s[1]), std::abs(s[2]) });
  }
  vtkSmartPointer<vtkVolumeImageAlgorithm> algorithm;
  if (method == REFERENCE)
  {
    algorithm = vtkSmartPointer<vtkVolumeReferenceIntegrator>::New();
  }
  else if (method == OBJECT_ORDER || method == OBJECT_ORDER_POINT)
  {
    auto caster = vtkSmartPointer<vtkObjectOrderRayCaster>::New();
    caster->SetSampleDistance(step);
    caster->SetClassification(method == OBJECT_ORDER ? vtkObjectOrderRayCaster::PREINTEGRATED
                                                     : vtkObjectOrderRayCaster::POINT_SAMPLED);
    algorithm = caster;
  }
  else
  {
    auto twin = vtkSmartPointer<vtkPreIntegrationRayCaster>::New();
    twin->SetSampleDistance(step);
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    table->SetTableSize(65);
    if (method == TWIN_FIRST)
    {
      table->SetDeviationSize(1);
      table->SetChordSize(65);
    }
    else
    {
      table->SetChordSize(17);
      table->SetDeviationSize(9);
    }
    twin->SetTable(table);
    algorithm = twin;
  }
  if (setup.Input)
  {
    algorithm->SetInputData(setup.Input);
  }
  algorithm->SetVolumeProperty(setup.Property);
  algorithm->SetCamera(setup.Camera);
  algorithm->SetImageSize(setup.Width, setup.Height);
  if (setup.Adjust)
  {
    setup.Adjust(algorithm);
  }
  return algorithm;
}

enum Expect
{
  IMAGE, // a non-empty image, within the method's tolerance of the reference's
  ERROR, // an error through the observers
  EITHER // one or the other; never an empty image without a message
};
const char* ExpectNames[] = { "image", "error", "image or error" };

struct Row
{
  std::string Case, Method, Outcome;
  double Seconds;
  bool Ok;
};
std::vector<Row> Table;

void Record(const std::string& name,
  const std::string& method,
  const std::string& outcome,
  double seconds,
  bool ok)
{
  Table.push_back({ name, method, outcome, seconds, ok });
  check(ok, name + " / " + method + ": " + outcome);
  check(seconds < TimeBound, name + " / " + method + " takes under the time bound");
}

// The first message of VTK's "In file, line n\nclass (address): message" text, shortened.
std::string Message(const std::string& text)
{
  const size_t start = text.find("): ");
  std::string message = start == std::string::npos ? text : text.substr(start + 3);
  message = message.substr(0, message.find('\n'));
  return message.size() > 100 ? message.substr(0, 97) + "..." : message;
}

std::string Describe(const Outcome& o)
{
  char text[128];
  if (o.Said.Errors)
  {
    return "error: " + Message(o.Said.Text);
  }
  std::snprintf(text,
    sizeof(text),
    "image, max alpha %.3f%s%s",
    o.MaxAlpha,
    o.Finite ? "" : ", NOT FINITE",
    o.Said.Warnings ? ", warned" : "");
  return text;
}

// Runs every method on setup; compare: a setup whose reference image the methods must match
// (defaults to the reference of setup itself).
void Case(const std::string& name,
  const Setup& setup,
  Expect expect,
  std::vector<Method>
    methods = { REFERENCE, OBJECT_ORDER, OBJECT_ORDER_POINT, TWIN_FIRST, TWIN_SECOND },
  const Setup* compare = nullptr)
{
  // Steps over a voxel have sampling errors beyond the methods' tolerances: no comparison.
  const bool coarse = !setup.DefaultStep && setup.Step >= 1.0;
  vtkSmartPointer<vtkImageData> reference;
  for (Method method : methods)
  {
    auto algorithm = Make(method, setup);
    const Outcome o = Run(algorithm);
    bool ok = o.Finite && o.Image;
    std::string outcome = Describe(o);
    if (o.Said.Errors)
    {
      ok = ok && expect != IMAGE && o.MaxAlpha == 0.0;
    }
    else
    {
      // An empty image needs a message; an image must match the reference's.
      ok = ok && expect != ERROR && (o.MaxAlpha > 0.0 || o.Said.Warnings > 0);
      if (ok && o.MaxAlpha > 0.0 && !coarse)
      {
        if (!reference)
        {
          auto ref = Make(REFERENCE, compare ? *compare : setup);
          const Outcome r = Run(ref);
          reference = r.Said.Errors ? nullptr : r.Image;
        }
        if (reference)
        {
          const double d = Difference(o.Image, reference);
          char text[64];
          std::snprintf(text, sizeof(text), ", %.4f from reference", d);
          outcome += text;
          ok = ok && d <= MethodTolerance[method];
        }
      }
    }
    Record(name,
      MethodNames[method],
      outcome + (ok ? "" : std::string(" (expected ") + ExpectNames[expect] + ")"),
      o.Seconds,
      ok);
  }
}

Setup Standard(vtkSmartPointer<vtkImageData> input)
{
  Setup s;
  s.Input = input;
  s.Property = Property();
  s.Camera = Camera(input);
  return s;
}

// An array of n values of the volume's type, attached as its scalars.
void Resize(vtkImageData* image, vtkIdType n)
{
  vtkDataArray* old = image->GetPointData()->GetScalars();
  vtkSmartPointer<vtkDataArray> values;
  values.TakeReference(old->NewInstance());
  values->SetName("scalars");
  values->SetNumberOfTuples(n);
  for (vtkIdType i = 0; i < n; ++i)
  {
    values->SetComponent(i, 0, old->GetComponent(i % old->GetNumberOfTuples(), 0));
  }
  image->GetPointData()->SetScalars(values);
}

void VolumeCases()
{
  Case("blobs 12^3", Standard(Blobs()), IMAGE);
  Case("blobs 2x2x2", Standard(Volume({ 2, 2, 2 }, Blob)), IMAGE);
  for (vtkIdType n : { 100, 1000 })
  {
    auto image = Blobs(VTK_FLOAT, 1.0, 8);
    Resize(image, n);
    Case("8^3 grid, " + std::to_string(n) + " values", Standard(image), ERROR);
  }
  {
    auto image = Blobs(VTK_FLOAT, 1.0, 8);
    Resize(image, 1000);
    image->SetDimensions(300, 300, 300);
    Case("300^3 grid, 1000 values", Standard(image), ERROR);
  }
  Case("no scalars", Standard(vtkSmartPointer<vtkImageData>::New()), ERROR);
  {
    auto image = Blobs();
    vtkNew<vtkFloatArray> three;
    three->SetNumberOfComponents(3);
    three->SetNumberOfTuples(image->GetNumberOfPoints());
    three->FillValue(0.5f);
    image->GetPointData()->SetScalars(three);
    Case("3 components", Standard(image), ERROR);
  }
  Case("slab 12x12x1", Standard(Volume({ 12, 12, 1 }, Blob)), ERROR);
  Case("1 voxel", Standard(Volume({ 1, 1, 1 }, Blob)), ERROR);
  Case("constant 0.9",
    Standard(Volume({ 6, 6, 6 }, [](double, double, double) { return 0.9; })),
    IMAGE);
  Case("constant 0 (transparent)",
    Standard(Volume({ 6, 6, 6 }, [](double, double, double) { return 0.0; })),
    EITHER);
  for (double fill : { 1e20, -1e20, 1e300, 9.007199254740993e15 })
  {
    char name[64];
    std::snprintf(name, sizeof(name), "constant %g", fill);
    Case(name,
      Standard(Volume(
        { 6, 6, 6 }, [fill](double, double, double) { return fill; }, VTK_DOUBLE)),
      EITHER);
  }
  // The reference cuts a cell into up to 1e6 pieces where its values span 1e300: few pixels.
  auto small = [](Setup s)
  {
    s.Width = s.Height = 6;
    return s;
  };
  Case("values +-1e300",
    small(Standard(Volume(
      { 6, 6, 6 }, [](double u, double v, double) { return u > v ? 1e300 : -1e300; }, VTK_DOUBLE))),
    EITHER);
  Case("values +-1.7e308 (range overflows)",
    Standard(Volume(
      { 6, 6, 6 },
      [](double u, double v, double) { return u > v ? 1.7e308 : -1.7e308; },
      VTK_DOUBLE)),
    EITHER);
  Case("doubles beyond float",
    small(Standard(Volume(
      { 6, 6, 6 }, [](double u, double, double) { return u > 0.5 ? 1e39 : 0.5; }, VTK_DOUBLE))),
    EITHER);
  Case("all NaN", Standard(Volume({ 6, 6, 6 }, [](double, double, double) { return NaN; })), ERROR);
  {
    Setup s = Standard(Volume({ 12, 12, 12 },
      [](double u, double v, double w) { return u < 0.2 && v < 0.2 ? NaN : Blob(u, v, w); }));
    Case("some NaN", s, EITHER);
  }
  Case("some Inf",
    Standard(Volume({ 6, 6, 6 }, [](double u, double, double) { return u > 0.7 ? Inf : 0.5; })),
    EITHER);
  for (int type : { VTK_CHAR,
         VTK_SIGNED_CHAR,
         VTK_UNSIGNED_CHAR,
         VTK_SHORT,
         VTK_UNSIGNED_SHORT,
         VTK_INT,
         VTK_UNSIGNED_INT,
         VTK_LONG,
         VTK_UNSIGNED_LONG,
         VTK_LONG_LONG,
         VTK_UNSIGNED_LONG_LONG,
         VTK_ID_TYPE,
         VTK_DOUBLE })
  {
    // 0..120 in every type: the transfer function over the same values.
    auto scaled = [](double u, double v, double w) { return std::round(120.0 * Blob(u, v, w)); };
    Setup s = Standard(Volume({ 12, 12, 12 }, scaled, type));
    s.Property = Property(0.0, 120.0);
    Setup asFloat = s;
    asFloat.Input = Volume({ 12, 12, 12 }, scaled, VTK_FLOAT);
    vtkSmartPointer<vtkDataArray> a;
    a.TakeReference(vtkDataArray::CreateDataArray(type));
    Case(std::string("scalar type ") + a->GetDataTypeAsString(),
      s,
      IMAGE,
      { REFERENCE, OBJECT_ORDER, TWIN_FIRST },
      &asFloat);
  }
  for (double spacing : { 1e-30, 1e-8, 1e8, 1e30 })
  {
    char name[64];
    std::snprintf(name, sizeof(name), "spacing %g", spacing);
    Case(name, Standard(Blobs(VTK_FLOAT, spacing)), EITHER);
  }
  {
    auto image = Blobs();
    image->SetOrigin(NaN, 0, 0);
    Setup s = Standard(Blobs());
    s.Input = image;
    Case("NaN origin", s, ERROR);
    auto flat = Blobs();
    flat->SetSpacing(1, 0, 1);
    s.Input = flat;
    Case("zero spacing", s, ERROR);
    auto singular = Blobs();
    const double direction[9] = { 1, 0, 0, 1, 0, 0, 0, 0, 1 };
    singular->SetDirectionMatrix(direction);
    s.Input = singular;
    Case("singular direction matrix", s, ERROR);
    auto inf = Blobs();
    inf->SetSpacing(Inf, 1, 1);
    s.Input = inf;
    Case("infinite spacing", s, ERROR);
  }
  {
    // The volume changed in place between two updates: the second image is the new volume's.
    for (Method method : { REFERENCE, OBJECT_ORDER, TWIN_FIRST })
    {
      auto image = Blobs();
      Setup s = Standard(image);
      auto algorithm = Make(method, s);
      Run(algorithm);
      vtkDataArray* values = image->GetPointData()->GetScalars();
      for (vtkIdType i = 0; i < values->GetNumberOfTuples(); ++i)
      {
        values->SetComponent(i, 0, 1.0 - values->GetComponent(i, 0));
      }
      values->Modified();
      const Outcome again = Run(algorithm);
      const Outcome fresh = Run(Make(method, s));
      const double d = Difference(again.Image, fresh.Image);
      Record("volume changed in place",
        MethodNames[method],
        "difference to a fresh update " + std::to_string(d),
        again.Seconds + fresh.Seconds,
        d == 0.0 && fresh.MaxAlpha > 0.0);
    }
  }
}

void SettingCases()
{
  const std::vector<Method> casters = { OBJECT_ORDER, OBJECT_ORDER_POINT, TWIN_FIRST, TWIN_SECOND };
  for (double step : { 0.0, -1.0, NaN, Inf, 1e-300, 1e-9 })
  {
    Setup s = Standard(Blobs());
    s.Step = step;
    s.DefaultStep = false;
    char name[64];
    std::snprintf(name, sizeof(name), "step %g", step);
    Case(name, s, ERROR, casters);
  }
  for (double step : { 1e-3, 4.0, 1e30 })
  {
    Setup s = Standard(Blobs());
    s.Step = step;
    s.DefaultStep = false;
    char name[64];
    std::snprintf(name, sizeof(name), "step %g", step);
    Case(name, s, step < 1.0 ? IMAGE : EITHER, casters);
  }
  for (double unit : { 1e-300, 1e-6, 1e6, 1e300 })
  {
    Setup s = Standard(Blobs());
    s.Property = Property(0.0, 1.0, unit);
    char name[64];
    std::snprintf(name, sizeof(name), "unit distance %g", unit);
    Case(name, s, EITHER);
  }
  for (double unit : { 0.0, -1.0, NaN })
  {
    Setup s = Standard(Blobs());
    s.Property = Property(0.0, 1.0, unit);
    char name[64];
    std::snprintf(name, sizeof(name), "unit distance %g", unit);
    Case(name, s, ERROR);
  }
  {
    Setup s = Standard(Blobs());
    s.Property->GetScalarOpacity()->RemoveAllPoints();
    Case("opacity function without points", s, EITHER);
    s = Standard(Blobs());
    s.Property->GetRGBTransferFunction()->RemoveAllPoints();
    Case("colour function without points", s, EITHER);
    s = Standard(Blobs());
    s.Property->GetScalarOpacity()->RemoveAllPoints();
    s.Property->GetScalarOpacity()->AddPoint(0.5, 0.3);
    Case("opacity function of 1 point", s, IMAGE);
    s = Standard(Blobs());
    s.Property->GetScalarOpacity()->AddPoint(0.7, 0.0);
    s.Property->GetScalarOpacity()->AddPoint(0.7, 0.9);
    s.Property->GetScalarOpacity()->AddPoint(0.7, 0.9);
    Case("opacity function with duplicate points", s, IMAGE);
    s = Standard(Blobs());
    s.Property->GetScalarOpacity()->RemoveAllPoints();
    s.Property->GetScalarOpacity()->AddPoint(0.0, 1.0);
    s.Property->GetScalarOpacity()->AddPoint(1.0, 1.0);
    Case("opacity 1 everywhere", s, IMAGE);
  }
  {
    Setup s = Standard(Blobs());
    s.Camera->SetPosition(5.5, 5.0, 5.2);
    s.Camera->SetFocalPoint(20, 5, 5);
    s.Camera->SetParallelScale(3.0);
    s.Camera->ParallelProjectionOff();
    Case("perspective camera inside the volume", s, EITHER);
    s.Camera->ParallelProjectionOn();
    Case("parallel camera inside the volume", s, EITHER);
    s = Standard(Blobs());
    s.Camera->SetPosition(5.5, 5.5, 40);
    s.Camera->SetFocalPoint(5.5, 5.5, 5.5);
    s.Camera->SetViewUp(0, 1, 0);
    Case("camera along the z axis", s, IMAGE);
    s = Standard(Blobs());
    s.Camera->SetPosition(5.5, 5.5, 5.5);
    s.Camera->SetFocalPoint(5.5, 5.5, 5.5);
    Case("camera at its focal point", s, ERROR);
    s = Standard(Blobs());
    s.Camera->SetPosition(5.5, 5.5, 40);
    s.Camera->SetFocalPoint(5.5, 5.5, 5.5);
    s.Camera->SetViewUp(0, 0, 1);
    Case("view up along the view direction", s, ERROR);
    for (double scale : { 0.0, 1e-300, 1e300 })
    {
      s = Standard(Blobs());
      s.Camera->SetParallelScale(scale);
      char name[64];
      std::snprintf(name, sizeof(name), "parallel scale %g", scale);
      Case(name, s, EITHER);
    }
    s = Standard(Blobs());
    s.Camera->SetPosition(1e300, 1e300, 1e300);
    Case("camera at 1e300", s, EITHER);
  }
  {
    Setup s = Standard(Blobs());
    s.Width = s.Height = 1;
    Case("image 1x1", s, EITHER);
    s.Width = s.Height = 100000;
    Case("image 100000x100000", s, ERROR, { REFERENCE, OBJECT_ORDER, TWIN_FIRST });
  }
  {
    // Steps the walker's float positions cannot resolve, though few enough samples.
    Setup s = Standard(Blobs());
    s.Step = 1e-7;
    s.DefaultStep = false;
    s.Adjust = [](vtkVolumeImageAlgorithm* a)
    { static_cast<vtkObjectOrderRayCaster*>(a)->SetMaximumSamplesPerRay(1e9); };
    Case("step 1e-7 voxel, 1e9 samples allowed", s, ERROR, { OBJECT_ORDER });
  }
  {
    // The object-order caster's placement matrix.
    for (double value : { 0.0, NaN })
    {
      Setup s = Standard(Blobs());
      s.Adjust = [value](vtkVolumeImageAlgorithm* a)
      {
        vtkNew<vtkMatrix4x4> m;
        m->SetElement(0, 0, value);
        static_cast<vtkObjectOrderRayCaster*>(a)->SetVolumeMatrix(m);
      };
      Case(std::string("volume matrix with ") + (value == 0.0 ? "zero" : "NaN"),
        s,
        ERROR,
        { OBJECT_ORDER });
    }
  }
}

// A table's Update() either builds or reports an error; never crashes or runs away.
void TableCases()
{
  auto property = Property();
  struct T
  {
    std::string Name;
    double Range[2];
    double Length;
    int Size;
    Expect Want;
  };
  const std::vector<T> cases = {
    { "range [0, 1]", { 0.0, 1.0 }, 1.0, 64, IMAGE },
    { "NaN range", { NaN, 1.0 }, 1.0, 64, ERROR },
    { "infinite range", { -Inf, Inf }, 1.0, 64, ERROR },
    { "range +-1.7e308", { -1.7e308, 1.7e308 }, 1.0, 64, EITHER },
    { "range [1e300, 1e300 + ulp]", { 1e300, std::nextafter(1e300, Inf) }, 1.0, 64, EITHER },
    { "segment 1e-300", { 0.0, 1.0 }, 1e-300, 64, EITHER },
    { "segment 1e300", { 0.0, 1.0 }, 1e300, 64, EITHER },
    { "segment Inf", { 0.0, 1.0 }, Inf, 64, ERROR },
    { "65536 entries per axis", { 0.0, 1.0 }, 1.0, 65536, EITHER },
  };
  for (int order : { 1, 2 })
  {
    for (const T& c : cases)
    {
      vtkSmartPointer<vtkPreIntegrationTable> table;
      if (order == 1)
      {
        table = vtkSmartPointer<vtkFirstOrderPreIntegrationTable>::New();
      }
      else
      {
        table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
      }
      Messages said;
      Listen(table, &said);
      table->SetVolumeProperty(property);
      table->SetScalarRange(c.Range[0], c.Range[1]);
      table->SetSegmentLength(c.Length);
      table->SetTableSize(c.Size);
      if (auto* chords = vtkSecondOrderPreIntegrationTable::SafeDownCast(table))
      {
        chords->SetChordSize(c.Size);
        chords->SetDeviationSize(c.Size);
      }
      const auto start = std::chrono::steady_clock::now();
      const bool built = table->Update();
      const double seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      bool finite = true;
      vtkFloatArray* values = table->GetTable();
      for (vtkIdType i = 0; built && i < values->GetNumberOfValues(); ++i)
      {
        finite = finite && std::isfinite(values->GetValue(i));
      }
      const bool ok =
        built ? c.Want != ERROR && finite && said.Errors == 0 : c.Want != IMAGE && said.Errors > 0;
      Record(c.Name,
        order == 1 ? "table-1" : "table-2",
        built ? (finite ? "built" : "built, NOT FINITE") : "error: " + Message(said.Text),
        seconds,
        ok);
    }
  }
}

// Sizer, octree, error metrics, ray model, sources of data, value classes.
void OtherCases()
{
  auto property = Property();
  {
    for (int n : { 100, 0 })
    {
      auto image = Blobs(VTK_FLOAT, 1.0, 8);
      if (n)
      {
        Resize(image, n);
      }
      vtkNew<vtkPreIntegrationTableSizer> sizer;
      sizer->SetNumberOfRays(64);
      vtkNew<vtkSecondOrderPreIntegrationTable> table;
      table->SetVolumeProperty(property);
      table->SetScalarRange(0.0, 1.0);
      table->SetSegmentLength(0.5);
      Messages said;
      Listen(sizer, &said);
      const bool chosen = sizer->Choose(image, image->GetPointData()->GetScalars(), table, 1, 0.5);
      Record(n ? "8^3 grid, 100 values" : "8^3 blobs",
        "sizer",
        chosen ? "chosen" : "error: " + Message(said.Text),
        0.0,
        n ? !chosen && said.Errors > 0 : chosen && said.Errors == 0);
    }
    auto nan = Volume({ 6, 6, 6 }, [](double, double, double) { return NaN; });
    vtkNew<vtkPreIntegrationTableSizer> sizer;
    vtkNew<vtkSecondOrderPreIntegrationTable> table;
    table->SetVolumeProperty(property);
    table->SetSegmentLength(0.5);
    Messages said;
    Listen(sizer, &said);
    const bool chosen = sizer->Choose(nan, nan->GetPointData()->GetScalars(), table, 2, 0.5);
    Record("all NaN",
      "sizer",
      chosen ? "chosen" : "error: " + Message(said.Text),
      0.0,
      !chosen && said.Errors > 0);
  }
  {
    // The caster's helpers report through the caster's observers.
    vtkNew<vtkObjectOrderRayCaster> caster;
    Messages said;
    Listen(caster, &said);
    const int dims[3] = { 8, 8, 8 };
    caster->GetOctree()->Build(nullptr, dims);
    Record("octree error", "objectorder", "error: " + Message(said.Text), 0.0, said.Errors == 1);
  }
  for (int order : { 1, 2 })
  {
    // A build stopped from its progress events: an error and an empty table; the next builds.
    vtkSmartPointer<vtkPreIntegrationTable> table;
    if (order == 1)
    {
      table = vtkSmartPointer<vtkFirstOrderPreIntegrationTable>::New();
    }
    else
    {
      table = vtkSmartPointer<vtkSecondOrderPreIntegrationTable>::New();
    }
    table->SetVolumeProperty(property);
    table->SetScalarRange(0.0, 1.0);
    table->SetTableSize(128);
    Messages said;
    Listen(table, &said);
    int events = 0;
    vtkNew<vtkCallbackCommand> abort;
    abort->SetClientData(&events);
    abort->SetCallback(
      [](vtkObject* caller, unsigned long, void* client, void*)
      {
        ++*static_cast<int*>(client);
        static_cast<vtkPreIntegrationTable*>(caller)->AbortBuildOn();
      });
    const unsigned long tag = table->AddObserver(vtkCommand::ProgressEvent, abort);
    const bool aborted = !table->Update();
    table->RemoveObserver(tag);
    table->Modified();
    const bool rebuilt = table->Update();
    Record("build aborted from a progress event",
      order == 1 ? "table-1" : "table-2",
      "error: " + Message(said.Text),
      0.0,
      aborted && events == 1 && said.Errors == 1 && rebuilt &&
        table->GetTable()->GetNumberOfTuples() == table->GetNumberOfEntries());
  }
  {
    vtkNew<vtkMinMaxOctree> octree;
    auto image = Blobs(VTK_FLOAT, 1.0, 8);
    Resize(image, 100);
    Messages said;
    Listen(octree, &said);
    const int dims[3] = { 8, 8, 8 };
    const bool built = octree->Build(image->GetPointData()->GetScalars(), dims);
    Record("8^3 grid, 100 values",
      "octree",
      built ? "built" : "error: " + Message(said.Text),
      0.0,
      !built && said.Errors > 0);
    const int bad[3] = { 0, -4, 8 };
    said = Messages();
    const bool none = octree->Build(image->GetPointData()->GetScalars(), bad);
    Record("dimensions 0 x -4 x 8",
      "octree",
      none ? "built" : "error: " + Message(said.Text),
      0.0,
      !none && said.Errors > 0);
  }
  {
    auto a = Run(Make(REFERENCE, Standard(Blobs())));
    Setup small = Standard(Blobs());
    small.Width = 7;
    auto b = Run(Make(REFERENCE, small));
    vtkNew<vtkRGBAErrorMetrics> metrics;
    metrics->SetInputData(a.Image);
    metrics->SetReferenceData(b.Image);
    const Outcome o = Run(metrics);
    Record("images of different sizes", "metrics", Describe(o), o.Seconds, o.Said.Errors > 0);
    vtkNew<vtkImageData> empty;
    metrics->SetReferenceData(empty);
    const Outcome e = Run(metrics);
    Record("reference without RGBA", "metrics", Describe(e), e.Seconds, e.Said.Errors > 0);
  }
  {
    vtkNew<vtkCameraRayModel> rays;
    Messages said;
    Listen(rays, &said);
    const bool none = rays->Prepare();
    Record("no camera", "ray model", none ? "prepared" : "error", 0.0, !none && said.Errors > 0);
    vtkNew<vtkCamera> camera;
    camera->SetPosition(1, 2, 3);
    camera->SetFocalPoint(1, 2, 3);
    rays->SetCamera(camera);
    said = Messages();
    const bool degenerate = rays->Prepare();
    Record("camera at its focal point",
      "ray model",
      degenerate ? "prepared" : "error",
      0.0,
      !degenerate && said.Errors > 0);
  }
  {
    vtkNew<vtkVolumeTransferFunctionSampler> sampler;
    Messages said;
    Listen(sampler, &said);
    vtkNew<vtkPiecewiseFunction> opacity;
    vtkNew<vtkColorTransferFunction> color;
    sampler->SetScalarOpacity(opacity);
    sampler->SetColor(color);
    const bool empty = sampler->Prepare();
    Record("functions without points",
      "sampler",
      empty ? "prepared" : "error",
      0.0,
      empty || said.Errors > 0);
    opacity->AddPoint(0.3, 0.5);
    opacity->AddPoint(0.3, 0.9);
    color->AddRGBPoint(0.3, 1, 0, 0);
    said = Messages();
    const bool duplicate = sampler->Prepare();
    double rgbTau[4];
    sampler->Evaluate(0.3, rgbTau);
    Record("duplicate points",
      "sampler",
      duplicate ? "prepared" : "error",
      0.0,
      duplicate && std::isfinite(rgbTau[3]) && sampler->GetMaximumOpacity(0.0, 1.0) >= 0.5);
  }
  {
    // The value classes: walks and profiles of NaN, infinite and zero rays end.
    vtkGridRayTraversal walk;
    const int dims[3] = { 8, 8, 8 };
    const double origins[][3] = { { NaN, 1, 1 }, { -1, 3, 3 }, { 1e300, 3, 3 }, { 3, 3, 3 } };
    const double directions[][3] = { { 1, 0, 0 }, { 0, 0, 0 }, { -1, 1e-300, 0 }, { Inf, 1, 0 } };
    for (int r = 0; r < 4; ++r)
    {
      int steps = 0, cell[3];
      double t0, t1;
      if (walk.Initialize(dims, origins[r], directions[r], 0.0, VTK_DOUBLE_MAX))
      {
        while (walk.Next(cell, t0, t1) && steps < 100000)
        {
          ++steps;
        }
      }
      Record("degenerate ray " + std::to_string(r),
        "grid traversal",
        std::to_string(steps) + " cells",
        0.0,
        steps <= 24);
    }
    vtkTrilinearRayProfile profile;
    const double corners[8] = { 0, 1, NaN, 1, 0, Inf, 1, 0 };
    const double u0[3] = { 0.5, 0.5, 0.5 }, v[3] = { 1, 0, 0 };
    profile.Set(corners, u0, v);
    double t = 0.0, lo, hi;
    profile.FindFirstCrossing(0.5, 1.0, t);
    profile.GetRange(1.0, lo, hi);
    Record("NaN and Inf corners", "ray profile", "evaluated", 0.0, true);
  }
  {
    vtkHierarchicalOcclusionMap map;
    map.Initialize(0, 0);
    map.Initialize(-5, 3);
    map.Initialize(1, 1);
    map.SetPixelOpaque(0, 0);
    Record("sizes 0x0, -5x3, 1x1",
      "occlusion map",
      std::to_string(map.GetNumberOfOpaquePixels()) + " opaque",
      0.0,
      map.GetNumberOfOpaquePixels() == 1 && map.IsRectangleOpaque(0, 0, 0, 0));
  }
}
}

int TestAdversarialInputs(int, char*[])
{
  hovrTest::MessageCapture messages; // anything not sent to observers is reported below
  VolumeCases();
  SettingCases();
  TableCases();
  OtherCases();

  size_t width = 0;
  for (const Row& row : Table)
  {
    width = std::max(width, row.Case.size());
  }
  std::printf(
    "%-*s  %-17s  %7s  %s\n", static_cast<int>(width), "case", "class", "seconds", "outcome");
  for (const Row& row : Table)
  {
    std::printf("%-*s  %-17s  %7.3f  %s%s\n",
      static_cast<int>(width),
      row.Case.c_str(),
      row.Method.c_str(),
      row.Seconds,
      row.Ok ? "" : "FAILED: ",
      row.Outcome.c_str());
  }
  const std::string stray = messages.Take();
  check(stray.find("ERROR") == std::string::npos,
    "every error goes to the observers, none to the output window: " + stray.substr(0, 400));
  return check.Result("TestAdversarialInputs");
}
