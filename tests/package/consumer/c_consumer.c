/* A C program against the installed package: cgamesh::cgamesh_c, the header cgamesh/cgamesh.h. */
#include <stdio.h>

#include <cgamesh/cgamesh.h>

int main(int argc, char** argv) {
  if (argc != 2) {
    fprintf(stderr, "usage: c_consumer MODEL.glb\n");
    return 2;
  }
  if (cgamesh_abi_version() != CGAMESH_C_ABI_VERSION) {
    fprintf(stderr, "ABI %d, header %d\n", cgamesh_abi_version(), CGAMESH_C_ABI_VERSION);
    return 1;
  }
  cgamesh_model* model = NULL;
  cgamesh_model_counts counts;
  if (cgamesh_model_load(argv[1], &model) != CGAMESH_OK || cgamesh_model_counts_get(model, &counts) != CGAMESH_OK) {
    fprintf(stderr, "%s\n", cgamesh_last_error());
    return 1;
  }
  printf("cgamesh %s (C): %d meshes, %d joints, %d clips\n", cgamesh_version(), counts.meshes, counts.joints,
         counts.clips);
  cgamesh_model_free(model);
  return counts.meshes > 0 ? 0 : 1;
}
