// hovr: higher-order volume rendering for VTK. BSD 3-Clause licence, see LICENSE.
// Shared by the hovr C++ tests: a check counter that says what failed, and a capture of VTK's
// messages so that expected errors never reach the console (ctest fails a test whose output
// matches "ERROR: ") while unexpected ones still fail the test.
#ifndef hovrTestUtilities_h
#define hovrTestUtilities_h

#include "vtkLogger.h"
#include "vtkNew.h"
#include "vtkOutputWindow.h"
#include "vtkSmartPointer.h"
#include "vtkStringOutputWindow.h"

#include <cmath>
#include <iostream>
#include <string>

namespace hovrTest
{
// Counts failed checks; each failure is printed with what was expected.
class Checker
{
public:
  bool operator()(bool ok, const std::string& what)
  {
    if (!ok)
    {
      std::cerr << "Failed: " << what << "\n";
      ++this->Failures;
    }
    return ok;
  }

  // Compares with an absolute tolerance and prints both values on failure.
  bool Near(double value, double expected, double tolerance, const std::string& what)
  {
    const bool ok = std::abs(value - expected) <= tolerance;
    if (!ok)
    {
      std::cerr << "Failed: " << what << ": got " << value << ", expected " << expected
                << " (difference " << value - expected << ", tolerance " << tolerance << ")\n";
      ++this->Failures;
    }
    return ok;
  }

  int GetFailures() const { return this->Failures; }

  // Test return value: 0 when every check passed.
  int Result(const char* test) const
  {
    if (this->Failures)
    {
      std::cerr << test << ": " << this->Failures << " checks failed\n";
      return 1;
    }
    return 0;
  }

private:
  int Failures = 0;
};

// Routes VTK's output window into a string for the lifetime of the object. VTK 9 also logs
// errors through vtkLogger to stderr, which is muted meanwhile.
class MessageCapture
{
public:
  MessageCapture()
    : Previous(vtkOutputWindow::GetInstance())
    , PreviousVerbosity(vtkLogger::GetCurrentVerbosityCutoff())
  {
    vtkOutputWindow::SetInstance(this->Window);
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  }
  ~MessageCapture()
  {
    vtkLogger::SetStderrVerbosity(this->PreviousVerbosity);
    vtkOutputWindow::SetInstance(this->Previous);
  }

  // Messages since the last call.
  std::string Take()
  {
    const std::string all = this->Window->GetOutput();
    const std::string recent = all.substr(this->Consumed);
    this->Consumed = all.size();
    return recent;
  }

  // True if an error containing fragment was reported since the last call.
  bool TakeError(const std::string& fragment)
  {
    const std::string text = this->Take();
    return text.find("ERROR") != std::string::npos && text.find(fragment) != std::string::npos;
  }

  // Checks that nothing was reported since the last call; prints it otherwise.
  bool ExpectNone(Checker& check, const std::string& when)
  {
    const std::string text = this->Take();
    return check(text.empty(), "no VTK message " + when + ", got: [" + text + "]");
  }

private:
  vtkSmartPointer<vtkOutputWindow> Previous;
  vtkLogger::Verbosity PreviousVerbosity;
  vtkNew<vtkStringOutputWindow> Window;
  size_t Consumed = 0;
};

// The settings every vtkPreIntegrationTable validates: starting from a table without transfer
// functions, each invalid setting makes Update() fail with an error naming it and builds
// nothing; then the valid settings (the property's functions, segment length validLength,
// range [0, 1], unit distance 1) build once, quietly.
template <class Table, class Property, class Color>
void CheckInvalidTableSettings(Checker& check,
  MessageCapture& messages,
  Table* table,
  Property* property,
  Color* color,
  double validLength)
{
  check(!table->Update(), "Update without transfer functions fails");
  check(messages.TakeError("colour transfer function"), "error for a missing colour function");
  table->GetSampler()->SetColor(color);
  check(!table->Update(), "Update without scalar opacity fails");
  check(messages.TakeError("scalar opacity function"), "error for a missing opacity function");
  table->SetVolumeProperty(property);
  for (double length : { 0.0, -1.0, std::nan("") })
  {
    table->SetSegmentLength(length);
    check(!table->Update(), "Update with segment length " + std::to_string(length) + " fails");
    check(
      messages.TakeError("segment length"), "error for segment length " + std::to_string(length));
  }
  table->SetSegmentLength(validLength);
  for (double upper : { 5.0, 4.0 })
  {
    table->SetScalarRange(5.0, upper);
    check(!table->Update(), "Update with scalar range [5, " + std::to_string(upper) + "] fails");
    check(messages.TakeError("scalar range"), "error for an empty scalar range");
  }
  table->SetScalarRange(0.0, 1.0);
  for (double u : { 0.0, -2.0 })
  {
    table->GetSampler()->SetScalarOpacityUnitDistance(u);
    check(!table->Update(), "Update with unit distance " + std::to_string(u) + " fails");
    check(messages.TakeError("unit distance"), "error for unit distance " + std::to_string(u));
  }
  check(table->GetBuildCount() == 0 && table->GetTable()->GetNumberOfTuples() == 0,
    "nothing is built from invalid settings");
  table->GetSampler()->SetScalarOpacityUnitDistance(1.0);
  check(table->Update() && table->GetBuildCount() == 1, "valid again after the fixes");
  messages.ExpectNone(check, "after restoring valid settings");
}
}

#endif
