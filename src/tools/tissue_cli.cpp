#include <cstdio>
int main() { std::puts("tissue_cli: not yet"); return 0; }
