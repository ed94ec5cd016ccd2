// Keeps hil_formats a valid library while it has no format of its own yet.
namespace hil::formats {
int formats_anchor() { return 0; }
}  // namespace hil::formats
