// Placeholder entry point replaced below once the force field exists.
int main() { return 0; }
