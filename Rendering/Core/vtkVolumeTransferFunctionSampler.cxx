// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
#include "vtkVolumeTransferFunctionSampler.h"

#include "vtkColorTransferFunction.h"
#include "vtkObjectFactory.h"
#include "vtkPiecewiseFunction.h"
#include "vtkSmartPointer.h"
#include "vtkVolumeProperty.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

vtkStandardNewMacro(vtkVolumeTransferFunctionSampler);
vtkCxxSetObjectMacro(vtkVolumeTransferFunctionSampler, Color, vtkColorTransferFunction);
vtkCxxSetObjectMacro(vtkVolumeTransferFunctionSampler, ScalarOpacity, vtkPiecewiseFunction);
vtkCxxSetObjectMacro(vtkVolumeTransferFunctionSampler, GrayColor, vtkPiecewiseFunction);

namespace
{
// One node of a piecewise function with up to three values (opacity: 1, colour: 3).
struct Node
{
  double X;
  double Y[3];
  double Midpoint;
  double Sharpness;
};

// VTK's interpolation between two nodes (vtkPiecewiseFunction::GetTable and
// vtkColorTransferFunction::GetTable in RGB): the position is remapped through the midpoint,
// then either held (sharpness > 0.99), linear (sharpness < 0.01) or a sharpened Hermite curve.
// Returns the weights (w1, w2, wt) of y1, y2 and the slope term for the caller to combine.
inline void InterpolateNodes(const Node& a, const Node& b, double x, int n, double* out)
{
  const double midpoint = std::min(std::max(a.Midpoint, 0.00001), 0.99999);
  const double sharpness = a.Sharpness;
  double s = (x - a.X) / (b.X - a.X);
  s = s < midpoint ? 0.5 * s / midpoint : 0.5 + 0.5 * (s - midpoint) / (1.0 - midpoint);
  if (sharpness > 0.99)
  {
    for (int c = 0; c < n; ++c)
    {
      out[c] = s < 0.5 ? a.Y[c] : b.Y[c];
    }
    return;
  }
  if (sharpness < 0.01)
  {
    for (int c = 0; c < n; ++c)
    {
      out[c] = (1.0 - s) * a.Y[c] + s * b.Y[c];
    }
    return;
  }
  if (s < 0.5)
  {
    s = 0.5 * std::pow(s * 2.0, 1.0 + 10.0 * sharpness);
  }
  else if (s > 0.5)
  {
    s = 1.0 - 0.5 * std::pow((1.0 - s) * 2.0, 1.0 + 10.0 * sharpness);
  }
  const double ss = s * s;
  const double sss = ss * s;
  const double h1 = 2.0 * sss - 3.0 * ss + 1.0;
  const double h2 = -2.0 * sss + 3.0 * ss;
  const double h3 = sss - 2.0 * ss + s;
  const double h4 = sss - ss;
  for (int c = 0; c < n; ++c)
  {
    const double t = (1.0 - sharpness) * (b.Y[c] - a.Y[c]);
    const double v = h1 * a.Y[c] + h2 * b.Y[c] + h3 * t + h4 * t;
    out[c] = std::min(std::max(v, std::min(a.Y[c], b.Y[c])), std::max(a.Y[c], b.Y[c]));
  }
}

// Smallest distance between adjacent distinct node positions of one or two node lists.
double SmallestGap(const std::vector<Node>& a, const std::vector<Node>* b)
{
  std::vector<double> xs;
  for (const Node& node : a)
  {
    xs.push_back(node.X);
  }
  if (b)
  {
    for (const Node& node : *b)
    {
      xs.push_back(node.X);
    }
  }
  std::sort(xs.begin(), xs.end());
  double smallest = VTK_DOUBLE_MAX;
  for (size_t i = 1; i < xs.size(); ++i)
  {
    if (xs[i] > xs[i - 1])
    {
      smallest = std::min(smallest, xs[i] - xs[i - 1]);
    }
  }
  return smallest;
}

// Evaluates a node list at x with clamping to the end values.
inline void EvaluateNodes(const std::vector<Node>& nodes, double x, int n, double* out)
{
  auto upper = std::upper_bound(
    nodes.begin(), nodes.end(), x, [](double v, const Node& node) { return v < node.X; });
  const Node* node = nullptr;
  if (upper == nodes.end())
  {
    node = &nodes.back();
  }
  else if (upper == nodes.begin())
  {
    node = &nodes.front();
  }
  if (node)
  {
    std::copy(node->Y, node->Y + n, out);
    return;
  }
  InterpolateNodes(*(upper - 1), *upper, x, n, out);
}

// Appends to curve a piecewise-linear RGB curve through color's own colours over its nodes
// (colour spaces other than RGB).
void FollowColorCurve(vtkColorTransferFunction* color,
  const std::vector<Node>& nodes,
  std::vector<Node>& curve)
{
  const bool step = color->GetColorSpace() == VTK_CTF_STEP;
  std::vector<double> ends, middles;
  if (color->GetColorSpace() == VTK_CTF_LAB_CIEDE2000)
  {
    // Its path depends on the range of the table asked for: the nodes' whole range, as a
    // colour map over the data, in one call (each computes the path anew).
    const double x0 = nodes.front().X, x1 = nodes.back().X;
    const int n = 1024 * static_cast<int>(nodes.size() - 1);
    ends.resize(3 * (n + 1));
    color->GetTable(x0, x1, n + 1, ends.data());
    for (int k = 0; k <= n; ++k)
    {
      const double x = k == 0 ? x0 : (k == n ? x1 : x0 + (x1 - x0) * k / n);
      curve.push_back(Node{ x, { ends[3 * k], ends[3 * k + 1], ends[3 * k + 2] }, 0.5, 0.0 });
    }
    return;
  }
  for (size_t i = 0; i + 1 < nodes.size(); ++i)
  {
    const double x0 = nodes[i].X, x1 = nodes[i + 1].X;
    if (step)
    {
      // VTK gives (x0, x1] the colour of x1: a jump just after each node.
      double rgb0[3], rgb1[3];
      color->GetColor(x0, rgb0);
      color->GetColor(x1, rgb1);
      curve.push_back(Node{ x0, { rgb0[0], rgb0[1], rgb0[2] }, 0.5, 0.0 });
      curve.push_back(Node{ std::nextafter(x0, x1), { rgb1[0], rgb1[1], rgb1[2] }, 0.5, 0.0 });
      continue;
    }
    // Uniform pieces, doubled until every piece's midpoint lies within 1e-6 of its chord
    // (one GetTable call per try: CIEDE2000 computes its path once per call).
    int n = 64;
    for (;;)
    {
      ends.resize(3 * (n + 1));
      color->GetTable(x0, x1, n + 1, ends.data());
      if (n >= 16384)
      {
        break;
      }
      const double h = (x1 - x0) / n;
      middles.resize(3 * n);
      color->GetTable(x0 + 0.5 * h, x1 - 0.5 * h, n, middles.data());
      double deviation = 0.0;
      for (int k = 0; k < n; ++k)
      {
        for (int c = 0; c < 3; ++c)
        {
          deviation = std::max(deviation,
            std::abs(middles[3 * k + c] - 0.5 * (ends[3 * k + c] + ends[3 * k + 3 + c])));
        }
      }
      if (!(deviation > 1e-6))
      {
        break;
      }
      n *= 2;
    }
    for (int k = 0; k < n; ++k)
    {
      const double x = k == 0 ? x0 : x0 + (x1 - x0) * k / n;
      curve.push_back(Node{ x, { ends[3 * k], ends[3 * k + 1], ends[3 * k + 2] }, 0.5, 0.0 });
    }
  }
  double rgb[3];
  color->GetColor(nodes.back().X, rgb);
  curve.push_back(Node{ nodes.back().X, { rgb[0], rgb[1], rgb[2] }, 0.5, 0.0 });
}
}

class vtkVolumeTransferFunctionSampler::vtkInternals
{
public:
  std::vector<Node> OpacityNodes;
  std::vector<Node> ColorNodes;
  // The colour as evaluated: ColorNodes in RGB; in other colour spaces a piecewise-linear RGB
  // curve through the function's own colours (RefineColor).
  std::vector<Node> ColorCurve;
  std::vector<double> Positions; // distinct node positions of both functions, ascending
  double InverseUnitDistance = 1.0;
  double MaximumOpacity = 1.0;
  vtkMTimeType PreparedTime = 0;
  double ContentHash = 0.0; // of what evaluation reads, after Prepare()
};

namespace
{
// FNV-1a over the bytes of the values evaluation reads.
void HashValues(uint64_t& hash, const double* values, size_t count)
{
  const auto* bytes = reinterpret_cast<const unsigned char*>(values);
  for (size_t i = 0; i < count * sizeof(double); ++i)
  {
    hash = (hash ^ bytes[i]) * 1099511628211ULL;
  }
}

void HashNodes(uint64_t& hash, const std::vector<Node>& nodes)
{
  for (const Node& node : nodes)
  {
    const double values[6] = {
      node.X, node.Y[0], node.Y[1], node.Y[2], node.Midpoint, node.Sharpness
    };
    HashValues(hash, values, 6);
  }
  const double separator = static_cast<double>(nodes.size());
  HashValues(hash, &separator, 1);
}
}

//------------------------------------------------------------------------------
vtkVolumeTransferFunctionSampler::vtkVolumeTransferFunctionSampler()
  : Internals(new vtkInternals)
{
}

//------------------------------------------------------------------------------
vtkVolumeTransferFunctionSampler::~vtkVolumeTransferFunctionSampler()
{
  this->SetColor(nullptr);
  this->SetGrayColor(nullptr);
  this->SetScalarOpacity(nullptr);
  delete this->Internals;
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::SetFromVolumeProperty(vtkVolumeProperty* property)
{
  if (!property)
  {
    this->SetColor(nullptr);
    this->SetGrayColor(nullptr);
    this->SetScalarOpacity(nullptr);
    return;
  }
  const bool rgb = property->GetColorChannels(0) == 3;
  this->SetColor(rgb ? property->GetRGBTransferFunction(0) : nullptr);
  this->SetGrayColor(rgb ? nullptr : property->GetGrayTransferFunction(0));
  this->SetScalarOpacity(property->GetScalarOpacity(0));
  this->SetScalarOpacityUnitDistance(property->GetScalarOpacityUnitDistance(0));
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::SetFromSampler(vtkVolumeTransferFunctionSampler* other)
{
  if (other && other != this)
  {
    this->SetColor(other->GetColor());
    this->SetGrayColor(other->GetGrayColor());
    this->SetScalarOpacity(other->GetScalarOpacity());
    this->SetScalarOpacityUnitDistance(other->GetScalarOpacityUnitDistance());
    this->SetMaximumOpacity(other->GetMaximumOpacity());
  }
}

//------------------------------------------------------------------------------
bool vtkVolumeTransferFunctionSampler::DeepCopy(vtkVolumeTransferFunctionSampler* other)
{
  if (other && other != this)
  {
    vtkSmartPointer<vtkColorTransferFunction> color;
    if (other->GetColor())
    {
      color = vtkSmartPointer<vtkColorTransferFunction>::New();
      color->DeepCopy(other->GetColor());
    }
    vtkSmartPointer<vtkPiecewiseFunction> gray, opacity;
    if (other->GetGrayColor())
    {
      gray = vtkSmartPointer<vtkPiecewiseFunction>::New();
      gray->DeepCopy(other->GetGrayColor());
    }
    if (other->GetScalarOpacity())
    {
      opacity = vtkSmartPointer<vtkPiecewiseFunction>::New();
      opacity->DeepCopy(other->GetScalarOpacity());
    }
    this->SetColor(color);
    this->SetGrayColor(gray);
    this->SetScalarOpacity(opacity);
    this->SetScalarOpacityUnitDistance(other->GetScalarOpacityUnitDistance());
    this->SetMaximumOpacity(other->GetMaximumOpacity());
  }
  return this->Prepare();
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::GetChangedRange(vtkVolumeTransferFunctionSampler* before,
  double range[2]) const
{
  const vtkInternals& now = *this->Internals;
  const vtkInternals& then = *before->Internals;
  const double infinity = std::numeric_limits<double>::infinity();
  range[0] = infinity;
  range[1] = -infinity;
  if (now.InverseUnitDistance != then.InverseUnitDistance ||
    now.MaximumOpacity != then.MaximumOpacity ||
    now.OpacityNodes.size() != then.OpacityNodes.size() ||
    now.ColorCurve.size() != then.ColorCurve.size() ||
    now.Positions.size() != then.Positions.size())
  {
    range[0] = -infinity;
    range[1] = infinity;
    return;
  }
  // A changed value at index i of an ascending list of positions: from its lower neighbour to
  // its upper one, old and new (beyond an end node, to infinity).
  auto widen = [&](
                 size_t i, size_t n, double lowNow, double lowThen, double highNow, double highThen)
  {
    range[0] = std::min(range[0], i == 0 ? -infinity : std::min(lowNow, lowThen));
    range[1] = std::max(range[1], i + 1 == n ? infinity : std::max(highNow, highThen));
  };
  for (const auto& lists : { std::make_pair(&now.OpacityNodes, &then.OpacityNodes),
         std::make_pair(&now.ColorCurve, &then.ColorCurve) })
  {
    const std::vector<Node>& a = *lists.first;
    const std::vector<Node>& b = *lists.second;
    for (size_t i = 0; i < a.size(); ++i)
    {
      if (a[i].X != b[i].X || a[i].Y[0] != b[i].Y[0] || a[i].Y[1] != b[i].Y[1] ||
        a[i].Y[2] != b[i].Y[2] || a[i].Midpoint != b[i].Midpoint ||
        a[i].Sharpness != b[i].Sharpness)
      {
        widen(i,
          a.size(),
          i > 0 ? a[i - 1].X : 0.0,
          i > 0 ? b[i - 1].X : 0.0,
          i + 1 < a.size() ? a[i + 1].X : 0.0,
          i + 1 < b.size() ? b[i + 1].X : 0.0);
      }
    }
  }
  const std::vector<double>& a = now.Positions;
  const std::vector<double>& b = then.Positions;
  for (size_t i = 0; i < a.size(); ++i)
  {
    if (a[i] != b[i])
    {
      widen(i,
        a.size(),
        i > 0 ? a[i - 1] : 0.0,
        i > 0 ? b[i - 1] : 0.0,
        i + 1 < a.size() ? a[i + 1] : 0.0,
        i + 1 < b.size() ? b[i + 1] : 0.0);
    }
  }
}

//------------------------------------------------------------------------------
bool vtkVolumeTransferFunctionSampler::IsColorEditOf(vtkVolumeTransferFunctionSampler* before) const
{
  const vtkInternals& now = *this->Internals;
  const vtkInternals& then = *before->Internals;
  auto same = [](const Node& a, const Node& b, bool values)
  {
    return a.X == b.X && a.Midpoint == b.Midpoint && a.Sharpness == b.Sharpness &&
      (!values || (a.Y[0] == b.Y[0] && a.Y[1] == b.Y[1] && a.Y[2] == b.Y[2]));
  };
  if (now.OpacityNodes.empty() || then.OpacityNodes.empty() ||
    now.InverseUnitDistance != then.InverseUnitDistance ||
    now.MaximumOpacity != then.MaximumOpacity || now.Positions != then.Positions ||
    now.OpacityNodes.size() != then.OpacityNodes.size() ||
    now.ColorCurve.size() != then.ColorCurve.size())
  {
    return false;
  }
  for (size_t i = 0; i < now.OpacityNodes.size(); ++i)
  {
    if (!same(now.OpacityNodes[i], then.OpacityNodes[i], true))
    {
      return false;
    }
  }
  for (size_t i = 0; i < now.ColorCurve.size(); ++i)
  {
    const double sharpness = now.ColorCurve[i].Sharpness;
    if (!same(now.ColorCurve[i], then.ColorCurve[i], false) ||
      (sharpness >= 0.01 && sharpness <= 0.99))
    {
      return false;
    }
  }
  return true;
}

//------------------------------------------------------------------------------
int vtkVolumeTransferFunctionSampler::GetNumberOfColorNodes() const
{
  return static_cast<int>(this->Internals->ColorCurve.size());
}

//------------------------------------------------------------------------------
int vtkVolumeTransferFunctionSampler::GetColorWeights(double s, double weights[2]) const
{
  const std::vector<Node>& nodes = this->Internals->ColorCurve;
  weights[0] = 1.0;
  weights[1] = 0.0;
  if (std::isnan(s) || nodes.empty())
  {
    weights[0] = 0.0;
    return 0;
  }
  // As EvaluateNodes and InterpolateNodes: the end values outside, else the two nodes around.
  auto upper = std::upper_bound(
    nodes.begin(), nodes.end(), s, [](double v, const Node& node) { return v < node.X; });
  if (upper == nodes.end() || upper == nodes.begin())
  {
    return upper == nodes.end() ? static_cast<int>(nodes.size()) - 1 : 0;
  }
  const Node& a = *(upper - 1);
  const Node& b = *upper;
  const double midpoint = std::min(std::max(a.Midpoint, 0.00001), 0.99999);
  double u = (s - a.X) / (b.X - a.X);
  u = u < midpoint ? 0.5 * u / midpoint : 0.5 + 0.5 * (u - midpoint) / (1.0 - midpoint);
  if (a.Sharpness > 0.99)
  {
    u = u < 0.5 ? 0.0 : 1.0;
  }
  weights[0] = 1.0 - u;
  weights[1] = u;
  return static_cast<int>(upper - nodes.begin()) - 1;
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::CombineColors(const double* weights, double rgb[3]) const
{
  rgb[0] = rgb[1] = rgb[2] = 0.0;
  const std::vector<Node>& nodes = this->Internals->ColorCurve;
  for (size_t k = 0; k < nodes.size(); ++k)
  {
    for (int c = 0; c < 3; ++c)
    {
      rgb[c] += weights[k] * nodes[k].Y[c];
    }
  }
}

//------------------------------------------------------------------------------
vtkMTimeType vtkVolumeTransferFunctionSampler::GetMTime()
{
  vtkMTimeType t = this->Superclass::GetMTime();
  if (this->Color)
  {
    t = std::max(t, this->Color->GetMTime());
  }
  if (this->GrayColor)
  {
    t = std::max(t, this->GrayColor->GetMTime());
  }
  if (this->ScalarOpacity)
  {
    t = std::max(t, this->ScalarOpacity->GetMTime());
  }
  return t;
}

//------------------------------------------------------------------------------
bool vtkVolumeTransferFunctionSampler::Prepare()
{
  const bool hasColor = this->Color && this->Color->GetSize() > 0;
  if (!hasColor && !(this->GrayColor && this->GrayColor->GetSize() > 0))
  {
    vtkErrorMacro("No colour transfer function (or one without nodes) was given.");
    return false;
  }
  if (!this->ScalarOpacity || this->ScalarOpacity->GetSize() < 1)
  {
    vtkErrorMacro("No scalar opacity function (or one without nodes) was given.");
    return false;
  }
  // Extinctions of 1/unit beyond float range make the float tables' inf * 0 = NaN.
  if (!(this->ScalarOpacityUnitDistance >= 1e-30 && this->ScalarOpacityUnitDistance <= 1e30))
  {
    vtkErrorMacro("The scalar opacity unit distance must lie in [1e-30, 1e30] (world units), got "
      << this->ScalarOpacityUnitDistance << "; rescale the volume's spacing.");
    return false;
  }
  vtkInternals& in = *this->Internals;
  const vtkMTimeType now = this->GetMTime();
  if (in.PreparedTime == now && !in.OpacityNodes.empty())
  {
    return true;
  }
  in.OpacityNodes.resize(this->ScalarOpacity->GetSize());
  for (size_t i = 0; i < in.OpacityNodes.size(); ++i)
  {
    double v[4];
    this->ScalarOpacity->GetNodeValue(static_cast<int>(i), v);
    in.OpacityNodes[i] = Node{ v[0], { v[1], 0.0, 0.0 }, v[2], v[3] };
  }
  in.ColorNodes.resize(hasColor ? this->Color->GetSize() : this->GrayColor->GetSize());
  for (size_t i = 0; i < in.ColorNodes.size(); ++i)
  {
    double v[6];
    if (hasColor)
    {
      this->Color->GetNodeValue(static_cast<int>(i), v);
      in.ColorNodes[i] = Node{ v[0], { v[1], v[2], v[3] }, v[4], v[5] };
    }
    else
    {
      this->GrayColor->GetNodeValue(static_cast<int>(i), v);
      in.ColorNodes[i] = Node{ v[0], { v[1], v[1], v[1] }, v[2], v[3] };
    }
  }
  auto byX = [](const Node& a, const Node& b) { return a.X < b.X; };
  std::stable_sort(in.OpacityNodes.begin(), in.OpacityNodes.end(), byX);
  std::stable_sort(in.ColorNodes.begin(), in.ColorNodes.end(), byX);
  in.Positions.clear();
  for (const auto* nodes : { &in.OpacityNodes, &in.ColorNodes })
  {
    for (const Node& node : *nodes)
    {
      in.Positions.push_back(node.X);
    }
  }
  std::sort(in.Positions.begin(), in.Positions.end());
  in.Positions.erase(std::unique(in.Positions.begin(), in.Positions.end()), in.Positions.end());
  in.ColorCurve = in.ColorNodes;
  if (hasColor && this->Color->GetColorSpace() != VTK_CTF_RGB && in.ColorNodes.size() > 1)
  {
    // Lab, Diverging, HSV and CIEDE2000 interpolate along curves in RGB, and Step jumps:
    // follow VTK's own colours, so that every method shows what VTK's mappers and ParaView
    // show.
    in.ColorCurve.clear();
    FollowColorCurve(this->Color, in.ColorNodes, in.ColorCurve);
  }
  in.InverseUnitDistance = 1.0 / this->ScalarOpacityUnitDistance;
  in.MaximumOpacity = this->MaximumOpacity;
  in.PreparedTime = now;
  uint64_t hash = 14695981039346656037ULL;
  HashNodes(hash, in.OpacityNodes);
  HashNodes(hash, in.ColorCurve);
  const double scalars[2] = { in.InverseUnitDistance, in.MaximumOpacity };
  HashValues(hash, scalars, 2);
  in.ContentHash = static_cast<double>(hash >> 11); // 53 bits: exact in a double
  return true;
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetContentHash() const
{
  return this->Internals->ContentHash;
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::EvaluateOpacity(double s) const
{
  if (std::isnan(s))
  {
    return 0.0;
  }
  double a;
  EvaluateNodes(this->Internals->OpacityNodes, s, 1, &a);
  return std::min(std::max(a, 0.0), this->Internals->MaximumOpacity);
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::EvaluateExtinction(double s) const
{
  return -std::log1p(-this->EvaluateOpacity(s)) * this->Internals->InverseUnitDistance;
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::Evaluate(double s, double rgbTau[4]) const
{
  if (std::isnan(s))
  {
    rgbTau[0] = rgbTau[1] = rgbTau[2] = rgbTau[3] = 0.0;
    return;
  }
  EvaluateNodes(this->Internals->ColorCurve, s, 3, rgbTau);
  rgbTau[3] = this->EvaluateExtinction(s);
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::Sample(double s0, double s1, int n, double* rgbTau) const
{
  for (int i = 0; i < n; ++i)
  {
    const double s = n > 1 ? s0 + (s1 - s0) * i / (n - 1.0) : 0.5 * (s0 + s1);
    this->Evaluate(s, rgbTau + 4 * i);
  }
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetMaximumOpacity(double s0, double s1) const
{
  if (s1 < s0)
  {
    std::swap(s0, s1);
  }
  double m = std::max(this->EvaluateOpacity(s0), this->EvaluateOpacity(s1));
  for (const Node& node : this->Internals->OpacityNodes)
  {
    if (node.X > s0 && node.X < s1)
    {
      m = std::max(m, std::min(std::max(node.Y[0], 0.0), this->Internals->MaximumOpacity));
    }
  }
  return m;
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetSmallestFeature() const
{
  return SmallestGap(this->Internals->OpacityNodes, &this->Internals->ColorNodes);
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetSmallestFeature(double s0, double s1) const
{
  const std::vector<double>& x = this->Internals->Positions;
  if (x.size() < 2)
  {
    return VTK_DOUBLE_MAX;
  }
  if (s1 < s0)
  {
    std::swap(s0, s1);
  }
  // The node intervals [x[i], x[i + 1]] that [s0, s1] overlaps (outside the nodes both
  // functions are constant).
  auto first = std::upper_bound(x.begin(), x.end(), s0);
  if (first == x.begin())
  {
    first = x.begin() + 1;
  }
  double smallest = VTK_DOUBLE_MAX;
  for (auto it = first; it != x.end() && *(it - 1) < s1; ++it)
  {
    smallest = std::min(smallest, *it - *(it - 1));
  }
  return smallest;
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetLongestSweep(double s,
  double tolerance,
  double widest,
  double cap) const
{
  const std::vector<double>& x = this->Internals->Positions;
  if (!(cap > 0.0) || !std::isfinite(s))
  {
    return std::max(cap, 0.0);
  }
  // The window (s - sigma, s + sigma) meets the same node intervals while sigma grows from the
  // distance of one node to the next: walk the nodes outwards from s in order of distance,
  // and stop at the first stretch where the tolerance allows less than reaching its far end.
  auto right = std::upper_bound(x.begin(), x.end(), s); // nearest node above s
  auto left = std::lower_bound(x.begin(), x.end(), s);  // one past the nearest node below s
  double reached = 0.0;                                 // a sweep known to be allowed
  for (;;)
  {
    const double toLeft = left != x.begin() ? s - *(left - 1) : VTK_DOUBLE_MAX;
    const double toRight = right != x.end() ? *right - s : VTK_DOUBLE_MAX;
    const double next = std::min(toLeft, toRight);
    // The features of the stretch (reached, next]: those the window meets just past reached.
    const double probe = next < VTK_DOUBLE_MAX ? 0.5 * (reached + next) : reached + 1.0;
    const double allowed =
      tolerance * std::min(this->GetSmallestFeature(s - probe, s + probe), widest);
    if (allowed < next || next >= cap)
    {
      return std::min(std::max(allowed, reached), cap);
    }
    reached = next;
    if (toLeft <= toRight)
    {
      --left;
    }
    else
    {
      ++right;
    }
  }
}

//------------------------------------------------------------------------------
double vtkVolumeTransferFunctionSampler::GetSmallestOpacityFeature() const
{
  return SmallestGap(this->Internals->OpacityNodes, nullptr);
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::GetNodeRange(double range[2]) const
{
  range[0] = VTK_DOUBLE_MAX;
  range[1] = -VTK_DOUBLE_MAX;
  for (const auto* nodes : { &this->Internals->OpacityNodes, &this->Internals->ColorNodes })
  {
    if (!nodes->empty())
    {
      range[0] = std::min(range[0], nodes->front().X);
      range[1] = std::max(range[1], nodes->back().X);
    }
  }
}

//------------------------------------------------------------------------------
void vtkVolumeTransferFunctionSampler::PrintSelf(ostream& os, vtkIndent indent)
{
  this->Superclass::PrintSelf(os, indent);
  os << indent << "Color: " << this->Color << "\n";
  os << indent << "GrayColor: " << this->GrayColor << "\n";
  os << indent << "ScalarOpacity: " << this->ScalarOpacity << "\n";
  os << indent << "ScalarOpacityUnitDistance: " << this->ScalarOpacityUnitDistance << "\n";
  os << indent << "MaximumOpacity: " << this->MaximumOpacity << "\n";
}
