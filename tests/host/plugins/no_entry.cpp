// A shared library without the ClothLab entry symbol.
extern "C" __attribute__((visibility("default"))) int clothlab_not_the_entry(void) { return 1; }
