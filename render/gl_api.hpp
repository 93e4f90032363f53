#pragma once
// OpenGL 3.3 core entry points, linked directly from libOpenGL (glvnd dispatches them to the
// context current on this thread, EGL or GLX alike), so no loader library is needed.

#ifndef GL_GLEXT_PROTOTYPES
#define GL_GLEXT_PROTOTYPES 1
#endif
#include <GL/glcorearb.h>
