// Anchor translation unit of cutwork::solvers (the solvers live in solvers/<topic>/).
namespace cutwork::solvers {
const char* library_name() { return "cutwork::solvers"; }
}  // namespace cutwork::solvers
