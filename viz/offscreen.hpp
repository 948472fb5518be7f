#pragma once
// What both viz programs need around VTK's off-screen rendering: a display check with the
// xvfb-run recipe (VTK from Debian aborts without X), the --size option, and writing the window
// to a PNG atomically.
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <regex>
#include <stdexcept>
#include <string>
#include <utility>

#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include <micromacro/io/vtk_messages.hpp>

namespace viz {

[[noreturn]] inline void fail(const std::string& what) { throw std::runtime_error(what); }

inline void require_display(const std::string& program) {
    const char* display = std::getenv("DISPLAY");
    if (!display || !*display)
        fail("no X display (DISPLAY is unset); VTK from Debian renders only through X: run under "
             "xvfb-run -a -s \"-screen 0 1280x1024x24\" " + program + " ...");
}

/// WIDTHxHEIGHT, each 16..8192 pixels.
inline std::pair<int, int> parse_size(const std::string& size) {
    std::smatch m;
    if (!std::regex_match(size, m, std::regex("([0-9]+)x([0-9]+)")))
        fail("--size '" + size + "' is not WIDTHxHEIGHT (e.g. 1000x800, each 16..8192 pixels)");
    auto pixels = [](const std::string& digits) { return digits.size() > 5 ? 100000 : std::stoi(digits); };  // beyond the limit either way
    const int width = pixels(m[1]), height = pixels(m[2]);
    if (width < 16 || height < 16 || width > 8192 || height > 8192)
        fail("--size " + size + " is outside 16..8192 pixels per side; give e.g. --size 1000x800");
    return {width, height};
}

/// Standard error sent to a temporary file while the object lives (the descriptor itself, so that
/// a C library's own prints are caught too): libpng prints "Write Error" before VTK reports a
/// failed write, and the program's message must come first. `release()` gives back standard
/// error and returns what was written to it.
class CapturedStandardError {
public:
    CapturedStandardError() {
        std::fflush(stderr);
        file_ = std::tmpfile();
        saved_ = ::dup(STDERR_FILENO);
        if (!file_ || saved_ < 0 || ::dup2(::fileno(file_), STDERR_FILENO) < 0) restore();
    }
    CapturedStandardError(const CapturedStandardError&) = delete;
    CapturedStandardError& operator=(const CapturedStandardError&) = delete;
    ~CapturedStandardError() {
        restore();
        if (file_) std::fclose(file_);
    }
    std::string release() {
        restore();
        std::string text;
        if (!file_) return text;
        std::rewind(file_);
        for (int c; (c = std::fgetc(file_)) != EOF;) text += static_cast<char>(c);
        while (!text.empty() && text.back() == '\n') text.pop_back();
        for (auto at = text.find('\n'); at != std::string::npos; at = text.find('\n', at)) text.replace(at, 1, "; ");
        return text;
    }

private:
    void restore() {
        if (saved_ < 0) return;
        std::fflush(stderr);
        ::dup2(saved_, STDERR_FILENO);
        ::close(saved_);
        saved_ = -1;
    }
    std::FILE* file_ = nullptr;
    int saved_ = -1;
};

/// Renders the window and writes it to `path` (a temporary name, then a rename).
inline void write_png(vtkRenderWindow* window, const std::filesystem::path& path) {
    const auto dir = path.has_parent_path() ? path.parent_path() : std::filesystem::path(".");
    if (!std::filesystem::is_directory(dir)) fail("cannot write " + path.string() + ": the directory " + dir.string() + " does not exist");
    window->Render();
    vtkNew<vtkWindowToImageFilter> grab;
    grab->SetInput(window);
    grab->ReadFrontBufferOff();
    grab->Update();
    const std::filesystem::path partial = path.string() + ".partial.png";
    vtkNew<vtkPNGWriter> png;
    const micromacro::io::VtkMessages vtk_said(png);  // quoted in the message, not printed by VTK first
    png->SetFileName(partial.string().c_str());
    png->SetInputConnection(grab->GetOutputPort());
    CapturedStandardError libpng_said;
    png->Write();  // says nothing: its error code and messages do
    const std::string libpng = libpng_said.release();
    micromacro::io::finish_vtk_write(png, true, vtk_said, partial, path, libpng);
    if (!libpng.empty()) std::fprintf(stderr, "%s\n", libpng.c_str());  // a warning of a write that succeeded
}

}  // namespace viz
