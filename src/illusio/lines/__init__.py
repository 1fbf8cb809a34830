"""Line drawings of meshes: apparent ridges (Judd et al. 2007) by the hybrid GPU method of Jardim &
de Figueiredo as the report describes it, beside silhouettes, suggestive contours, ridges & valleys
and image edges."""
