// Anchor translation unit of cutwork::kernels (the kernels live in kernels/<op>/).
namespace cutwork::kernels {
const char* library_name() { return "cutwork::kernels"; }
}  // namespace cutwork::kernels
