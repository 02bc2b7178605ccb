/* faker/opengl.c — libOpenGL.so.0 of the faker: glvnd's GL-only library,
 * which libGLU.so.1 and glvnd-linked programs name. It defines nothing: it
 * depends on the faker's libGL.so.1 (linked --no-as-needed), which defines
 * every gl*, so imports through it bind to the same entry points and the
 * same current context. */
typedef int tsr_faker_opengl_has_no_code;
