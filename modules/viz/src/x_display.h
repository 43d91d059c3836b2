#pragma once
// Private to viz: an X connection that render() opens before VTK touches X, so that a
// missing display becomes an exception instead of VTK's abort(). Xlib's headers stay in
// display.cpp (they define macros such as None, Status and Bool).

namespace plantnbv {
namespace viz {
namespace detail {

/// \brief Owns a connection to the X server at $DISPLAY.
class XDisplayConnection {
public:
  /// \throws Error with requireDisplay()'s message when no X server answers.
  XDisplayConnection();
  ~XDisplayConnection();
  XDisplayConnection(const XDisplayConnection&) = delete;
  XDisplayConnection& operator=(const XDisplayConnection&) = delete;

  /// \brief The Xlib `Display*`, for vtkRenderWindow::SetDisplayId.
  void* handle() const { return display_; }

private:
  void* display_ = nullptr;
};

} // namespace detail
} // namespace viz
} // namespace plantnbv
