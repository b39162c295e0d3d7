#include "io/vtk_message_capture.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <algorithm>
#include <cctype>
#include <vector>

namespace tc {

class CapturingOutputWindow : public vtkOutputWindow {
public:
    static CapturingOutputWindow* New();
    vtkTypeMacro(CapturingOutputWindow, vtkOutputWindow);

    void DisplayText(const char* text) override {
        if (!text) return;
        MessageTypes type = GetCurrentMessageType();
        bool warning = type == MESSAGE_TYPE_WARNING || type == MESSAGE_TYPE_GENERIC_WARNING;
        if (type == MESSAGE_TYPE_ERROR || (warning && warningsFail)) messages.emplace_back(text);
    }

    bool warningsFail = true;
    std::vector<std::string> messages;
};
vtkStandardNewMacro(CapturingOutputWindow);

namespace {

std::mutex& captureMutex() {
    static std::mutex m;
    return m;
}

}  // namespace

VtkMessageCapture::VtkMessageCapture(bool warningsFail)
    : m_lock(captureMutex()), m_window(vtkSmartPointer<CapturingOutputWindow>::New()) {
    // VTK 9 also sends every message through vtkLogger (loguru), whose stderr sink prints it
    // regardless of the output window. tubecast reports VTK problems as exceptions, so the sink
    // is switched off for the process, once (vtkLogger has no getter to restore).
    static std::once_flag quietLogger;
    std::call_once(quietLogger, [] { vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF); });
    m_window->warningsFail = warningsFail;
    m_previous = vtkOutputWindow::GetInstance();
    vtkOutputWindow::SetInstance(m_window);
}

VtkMessageCapture::~VtkMessageCapture() {
    vtkOutputWindow::SetInstance(m_previous);
}

bool VtkMessageCapture::failed() const {
    return !m_window->messages.empty();
}

std::string VtkMessageCapture::firstError() const {
    if (m_window->messages.empty()) return {};
    std::string text = m_window->messages.front();
    if (text.rfind("ERROR: In ", 0) == 0 || text.rfind("Warning: In ", 0) == 0 ||
        text.rfind("Generic Warning: In ", 0) == 0) {
        std::size_t nl = text.find('\n');
        text = nl == std::string::npos ? std::string() : text.substr(nl + 1);
    }
    // Drop the "ClassName (0x1234): " prefix.
    std::size_t paren = text.find(" (0x");
    std::size_t close = paren == std::string::npos ? paren : text.find("): ", paren);
    if (close != std::string::npos && text.find('\n') > close) text = text.substr(close + 3);
    // The legacy reader appends " for file: PATH"; callers print the path first already.
    if (std::size_t forFile = text.find(" for file: "); forFile != std::string::npos) text.erase(forFile);
    while (!text.empty() && std::isspace(static_cast<unsigned char>(text.back()))) text.pop_back();
    std::replace(text.begin(), text.end(), '\n', ' ');
    return text.empty() ? "unknown error" : text;
}

}  // namespace tc
