// The file the nodes' shared precompiled header is built with (CMakeLists.txt, TT_NODE_PCH).
