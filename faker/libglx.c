/* faker/libglx.c — libGLX.so.0 of the faker: glvnd's GLX library, which
 * programs built against glvnd (VTK's rendering library, through GLEW)
 * name for their glX* calls. It defines nothing: it depends on the faker's
 * libGL.so.1 (linked --no-as-needed), which defines every glX* and gl*, so
 * the program's glX* calls bind to the faker's GLX and make current the
 * same contexts its gl* calls draw with — never to the system's GLX next
 * to the faker's GL. */
typedef int tsr_faker_glx_has_no_code;
