#pragma once
// Turns what VTK prints into tubecast errors. VTK routes every vtkErrorMacro / vtkWarningMacro
// without an observer to the process-global vtkOutputWindow, including those of internal objects
// (the XML parser, readers' parsers, the executive) that cannot be observed directly; a
// VtkMessageCapture installs a collecting window for its lifetime so readers and the stream
// tracer can report the first message as an InputError naming the file.
#include <vtkNew.h>
#include <vtkSmartPointer.h>

#include <mutex>
#include <string>

class vtkOutputWindow;

namespace tc {

class CapturingOutputWindow;

class VtkMessageCapture {
public:
    // Warnings count as failures too when `warningsFail` (the legacy reader only warns about a
    // truncated ASCII array and returns what it got); the stream tracer warns about ordinary
    // events (a seed outside the grid) and passes false.
    explicit VtkMessageCapture(bool warningsFail = true);
    ~VtkMessageCapture();
    VtkMessageCapture(const VtkMessageCapture&) = delete;
    VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;

    bool failed() const;
    // "ERROR: In /build/.../vtkDataReader.cxx, line 123\nvtkPolyDataReader (0x55d0): Unable to
    // open file\n\n" -> "Unable to open file": the first captured message, its message line only
    // (later ones are the pipeline's "Algorithm ... returned failure" echo); empty if none.
    std::string firstError() const;

private:
    // The output window is process-global: one mutex serialises everything in tubecast that
    // talks to VTK through a capture.
    std::lock_guard<std::mutex> m_lock;
    vtkSmartPointer<vtkOutputWindow> m_previous;
    vtkSmartPointer<CapturingOutputWindow> m_window;
};

}  // namespace tc
