// Only dimensions 2 and 3 exist.
// expect-error: template constraint failure.*DimTraits
#include <micromacro/micromacro.hpp>

int main() {
    micromacro::DimTraits<4>::Vec v;
    return static_cast<int>(v.size());
}
