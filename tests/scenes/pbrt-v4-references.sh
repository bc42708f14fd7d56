#!/bin/bash
# Renders the pbrt-v4 references of tests/test_pbrt_reference.cpp: each named scene of this
# folder by pbrt-v4 at 1024 spp (media_walk 4096) into NAME.exr beside it.
#   tests/scenes/pbrt-v4-references.sh PBRT_BINARY [NAME ...]   (default: every reference)
# pbrt-v4 is built by the lead's tools (not part of manylight); any pbrt-v4 build will do.
set -euo pipefail
pbrt=${1:?usage: $0 PBRT_BINARY [NAME ...]}
shift
cd "$(dirname "$0")"
names=("$@")
[ ${#names[@]} -gt 0 ] || names=(camera_orthographic camera_orthographic_lens camera_equirect
  camera_equalarea tex_bilerp tex_dots tex_fbm tex_wrinkled tex_windy tex_marble tex_mix
  tex_directionmix mat_thindielectric mat_mix shape_cylinder media_fog media_grid
  light_goniometric light_projection light_area_image mat_coateddiffuse mat_coatedconductor
  mat_coatedconductor_depth2 mat_interface media_cloud media_walk media_nanovdb mat_normalmap media_fire
  media_caustic shape_curve shape_curve_alpha shape_curve_motion mat_hair camera_realistic
  camera_realistic_star camera_realistic_image shape_loopsubdiv film_crop light_alpha light_portal light_invisible
  mat_measured mat_measured_aniso)
for n in "${names[@]}"; do
  echo "== $n"
  spp=1024
  [ "$n" = media_walk ] && spp=4096  # random walks in dense media: noisy
  "$pbrt" --quiet --spp "$spp" --seed 1 --outfile "$n.exr" "$n.pbrt"
done
