// The text of suffuse plot's figures: one font, black, at a given size.
#pragma once

class vtkTextProperty;

namespace suffuse::plot {

// DejaVu Sans when installed (Debian's fonts-dejavu-core), else VTK's built-in
// sans-serif font (whose Debian build draws '[' and ']' as parentheses).
void style_text(vtkTextProperty* text, int size, bool bold);

}  // namespace suffuse::plot
