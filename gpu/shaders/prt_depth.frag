// Depth map: depth only.
void main() {}
