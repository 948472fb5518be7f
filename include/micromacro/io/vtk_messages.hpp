#pragma once
// VTK's own error and warning messages of one algorithm (a writer, a reader), kept instead of
// printed: VTK prints an object's message to standard error only when nothing observes its error
// and warning events. A failure is then told once, by the program's own message, which may quote
// what VTK said (the first lines a user reads on a full disk are the program's, not VTK's log).
#include <string>

#include <vtkAlgorithm.h>
#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkExecutive.h>
#include <vtkNew.h>

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

}  // namespace micromacro::io
