#pragma once
// VTK's own error and warning messages of one algorithm (a writer, a reader), kept instead of
// printed: VTK prints an object's message to standard error only when nothing observes its error
// and warning events. A failure is then told once, by the program's own message, which may quote
// what VTK said (the first lines a user reads on a full disk are the program's, not VTK's log).
// `finish_vtk_write` ends every VTK writer's file the one way: renamed into place, or removed.
#include <filesystem>
#include <string>
#include <system_error>

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkErrorCode.h>
#include <vtkExecutive.h>
#include <vtkNew.h>

#include "micromacro/core/error.hpp"

namespace micromacro::io {

class VtkMessages {
public:
    /// Observes `algorithm` and its executive (which reports the pipeline's failures) from now
    /// on; the object must outlive neither.
    explicit VtkMessages(vtkAlgorithm* algorithm) {
        command_->SetClientData(this);
        command_->SetCallback([](vtkObject*, unsigned long event, void* self, void* message) {
            auto& kept = *static_cast<VtkMessages*>(self);
            // "ERROR: In FILE, line N\nCLASS (ADDRESS): WHAT\n\n": WHAT is kept.
            std::string line = message ? static_cast<const char*>(message) : "";
            if (const auto at = line.find("): "); at != std::string::npos) line = line.substr(at + 3);
            while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
            const bool error = event == vtkCommand::ErrorEvent;
            kept.errors_ += error;
            kept.text_ += (kept.text_.empty() ? "" : "; ") + std::string(error ? "" : "warning: ") + line;
        });
        for (vtkObject* object : {static_cast<vtkObject*>(algorithm), static_cast<vtkObject*>(algorithm->GetExecutive())}) {
            object->AddObserver(vtkCommand::ErrorEvent, command_);
            object->AddObserver(vtkCommand::WarningEvent, command_);
        }
    }
    VtkMessages(const VtkMessages&) = delete;
    VtkMessages& operator=(const VtkMessages&) = delete;

    /// What VTK said, joined by "; " (empty: nothing).
    const std::string& text() const { return text_; }
    /// Whether VTK reported an error (not only warnings).
    bool any_error() const { return errors_ > 0; }

private:
    std::string text_;
    int errors_ = 0;
    vtkNew<vtkCallbackCommand> command_;
};

/// After `writer` wrote (`wrote`: it said so) the temporary file `partial` of `path`: renamed
/// to `path`, or, if the writer failed by any sign (a full disk leaves a truncated file and only
/// an error code), removed, and the failure thrown with what VTK said and `also` said.
inline void finish_vtk_write(vtkAlgorithm* writer, bool wrote, const VtkMessages& said, const std::filesystem::path& partial,
                             const std::filesystem::path& path, const std::string& also = "") {
    const unsigned long code = writer->GetErrorCode();
    if (!wrote || code != vtkErrorCode::NoError || said.any_error() || !std::filesystem::is_regular_file(partial)) {
        std::error_code ignored;
        std::filesystem::remove(partial, ignored);
        throw_input_error("cannot write ", path.string(), ": VTK's writer failed (",
                          code != vtkErrorCode::NoError ? vtkErrorCode::GetStringFromErrorCode(code) : "no error code",
                          said.text().empty() ? "" : ": " + said.text(), also.empty() ? "" : "; " + also,
                          "; is the disk full or the directory not writable?)");
    }
    std::error_code renamed;
    std::filesystem::rename(partial, path, renamed);
    if (renamed) throw_input_error("cannot rename ", partial.string(), " to ", path.string(), ": ", renamed.message());
}

}  // namespace micromacro::io
