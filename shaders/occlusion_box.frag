#version 450 core
// The boxes of the occlusion queries write nothing: the query counts the samples that pass the depth test.

void main() {}
