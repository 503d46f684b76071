complete -c scene-render -s o -l output -d 'Output image; `-` is standard output. Default: standard output, or no image with --compare (only the report)' -r
complete -c scene-render -l format -d 'Image format; by default from the output\'s extension (.png, .ppm, .pnm, .pam, .pfm), PNG on standard output. PFM stores the frame\'s linear-light values as 32-bit floats, unrounded, and no alpha' -r -f -a "png\t'PNG, lossless, with alpha when the image has transparency'
ppm\t'Binary PPM (P6); transparency is flattened'
pam\t'PAM (P7), RGB or RGB_ALPHA'
pfm\t'PFM (Portable Float Map, `PF`): RGB in linear light, 32-bit floats, little-endian, rows bottom to top; no alpha'"
complete -c scene-render -l depth -d 'Bits per channel of PNG, PPM and PAM output: 8, or 16 (each code the nearest to the exact sRGB value; MAXVAL 65535 in PPM and PAM). Not for PFM, which is float, nor --animate' -r -f -a "8\t'8 bits, codes 0..=255'
16\t'16 bits, codes 0..=65535 (PNG bit depth 16, netpbm MAXVAL 65535)'"
complete -c scene-render -l size -d 'Image size (WxH). The default is the IRIS screen' -r
complete -c scene-render -l background -d 'Background colour (`r,g,b` or `#rrggbb`), or `none`: what polygons leave uncovered is transparent, and the image carries their coverage as alpha (PNG, PAM). The frame is drawn twice: 1.6x the whole process\'s time on 10,000 random triangles in one run (bench/RESULTS-same-images.md)' -r
complete -c scene-render -l background-pattern -d 'A .pat or an image (PNG, JPEG, ...: told by content) tiled over the background in screen mode (the thesis\'s colorclear): pixel (x, y) from the lower-left takes texel (x mod W, y mod H), an image\'s bottom row being texel row 0; transparent texels (alpha below one half) show --background' -r
complete -c scene-render -l camera -d 'Camera JSON file (`-` = standard input); excludes every other camera flag. Default: none (the tool\'s default view)' -r
complete -c scene-render -l lookat -d 'IRIS/GLU lookat: eye and center points. Default: none (identity view, eye at the origin looking down -z)' -r
complete -c scene-render -l up -d 'Up direction for --lookat. Default: 0,1,0' -r
complete -c scene-render -l twist -d 'IRIS lookat twist in degrees (right-hand rotation of the camera about its line of sight). Default: 0' -r
complete -c scene-render -l perspective -d 'gluPerspective: vertical field of view in degrees, aspect (width/height, or `auto` for the image\'s own), near and far distances (near may be 0). Default: none' -r
complete -c scene-render -l ortho -d 'glOrtho: left, right, bottom, top, near, far in eye coordinates. Default: none' -r
complete -c scene-render -l ortho2 -d 'IRIS ortho2 (gluOrtho2D): left, right, bottom, top; near -1, far 1. Default: none' -r
complete -c scene-render -l vrp -d 'Textbook view reference point (world). Default: 0,0,0' -r
complete -c scene-render -l vpn -d 'View plane normal: the direction the camera looks. Default: 0,0,-1 (-1,-1,-1 with --oblique isometric)' -r
complete -c scene-render -l view-up -d 'View-up direction (world), shown vertical on the image. Default: 0,1,0' -r
complete -c scene-render -l view-distance -d 'Distance from the VRP to the view plane along the VPN. Default: 0' -r
complete -c scene-render -l window -d 'Window on the view plane (view plane coordinates, centred on the VPN line through the VRP); it fills the image. Default: none (required)' -r
complete -c scene-render -l cop -d 'Perspective: centre of projection (world coordinates, on the viewer\'s side of the view plane). Default: none' -r
complete -c scene-render -l dop -d 'Parallel: direction of projection (world; oblique when not along the VPN). Default: none' -r
complete -c scene-render -l oblique -d 'Parallel: cavalier or cabinet oblique projection with the receding axis at ANGLE degrees (default 45), or isometric (no angle). Default: none' -r
complete -c scene-render -l front -d 'Front clipping plane: distance from the VRP along the VPN. Default: none (required)' -r
complete -c scene-render -l back -d 'Back clipping plane: distance from the VRP along the VPN. Default: none (required)' -r
complete -c scene-render -l boundary -d 'What a pattern shows outside its bounds (texel columns and rows outside 0..SIZE), XGL\'s boundary conditions: repeat (XGL wrap; the tiling of patkit-stream(5)), transparent (the polygon\'s own colour, as if untextured), clamp (the --boundary-color), mirror, edge (the closest boundary texel). A record\'s "pattern" key "boundary" overrides it' -r -f -a "repeat\t'`XGL_TEXTURE_BOUNDARY_WRAP`: the pattern repeats (the tiling of patkit-stream(5); OpenGL\'s `GL_REPEAT`)'
transparent\t'`XGL_TEXTURE_BOUNDARY_TRANSPARENT`: "finish rendering as though texturing were not being done": the polygon\'s own colour'
clamp\t'`XGL_TEXTURE_BOUNDARY_CLAMP`: a constant colour (`--boundary-color`)'
mirror\t'`XGL_TEXTURE_BOUNDARY_MIRROR`: every other copy reversed'
edge\t'`XGL_TEXTURE_BOUNDARY_CLAMP_BOUNDARY`: the closest boundary texel (OpenGL\'s clamp to edge)'"
complete -c scene-render -l boundary-u -d 'The boundary condition along u only (overrides --boundary). When u and v differ and both exceed the bounds, XGL\'s precedence decides: transparent, clamp, repeat, mirror, edge. A record\'s "boundary_u" overrides it' -r -f -a "repeat\t'`XGL_TEXTURE_BOUNDARY_WRAP`: the pattern repeats (the tiling of patkit-stream(5); OpenGL\'s `GL_REPEAT`)'
transparent\t'`XGL_TEXTURE_BOUNDARY_TRANSPARENT`: "finish rendering as though texturing were not being done": the polygon\'s own colour'
clamp\t'`XGL_TEXTURE_BOUNDARY_CLAMP`: a constant colour (`--boundary-color`)'
mirror\t'`XGL_TEXTURE_BOUNDARY_MIRROR`: every other copy reversed'
edge\t'`XGL_TEXTURE_BOUNDARY_CLAMP_BOUNDARY`: the closest boundary texel (OpenGL\'s clamp to edge)'"
complete -c scene-render -l boundary-v -d 'The boundary condition along v only (overrides --boundary). A record\'s "boundary_v" overrides it' -r -f -a "repeat\t'`XGL_TEXTURE_BOUNDARY_WRAP`: the pattern repeats (the tiling of patkit-stream(5); OpenGL\'s `GL_REPEAT`)'
transparent\t'`XGL_TEXTURE_BOUNDARY_TRANSPARENT`: "finish rendering as though texturing were not being done": the polygon\'s own colour'
clamp\t'`XGL_TEXTURE_BOUNDARY_CLAMP`: a constant colour (`--boundary-color`)'
mirror\t'`XGL_TEXTURE_BOUNDARY_MIRROR`: every other copy reversed'
edge\t'`XGL_TEXTURE_BOUNDARY_CLAMP_BOUNDARY`: the closest boundary texel (OpenGL\'s clamp to edge)'"
complete -c scene-render -l boundary-color -d 'The constant colour of --boundary clamp (`r,g,b` or `#rrggbb`). A record\'s "boundary_color" overrides it' -r
complete -c scene-render -l compose -d 'How texels combine with the polygon\'s "color" (XGL\'s composition methods, in linear light): replace, modulate (texel x color), blend (between --compose-color1 and --compose-color2 by the texel), blend-intrinsic (between color and --compose-color1), decal and decal-intrinsic (transparent texels show --compose-color1 or color; XGL allows decal only for maps with alpha: patterns with transparent texels). A record\'s "pattern" key "compose" overrides it' -r -f -a "replace\t'`XGL_TEXTURE_OP_REPLACE`: the texel replaces the polygon\'s colour (patkit-stream(5); transparent texels show what is behind)'
modulate\t'`XGL_TEXTURE_OP_MODULATE`: texel times the polygon\'s colour'
blend\t'`XGL_TEXTURE_OP_BLEND`: two constants blended by the texel, `c1 (1 - t) + c2 t` per channel'
blend-intrinsic\t'`XGL_TEXTURE_OP_BLEND_INTRINSIC`: the polygon\'s colour and a constant blended by the texel, `color (1 - t) + c1 t`'
decal\t'`XGL_TEXTURE_OP_DECAL`: the texel where opaque, the constant `c1` where transparent'
decal-intrinsic\t'`XGL_TEXTURE_OP_DECAL_INTRINSIC`: the texel where opaque, the polygon\'s colour where transparent'"
complete -c scene-render -l compose-color1 -d 'First constant colour of --compose blend, blend-intrinsic and decal. A record\'s "compose_color1" overrides it' -r
complete -c scene-render -l compose-color2 -d 'Second constant colour of --compose blend. A record\'s "compose_color2" overrides it' -r
complete -c scene-render -l filter -d 'How a textured pixel is computed from the pattern: box (the exact area integral of the texels under the pixel, crisp, for fragments meeting up to 65,536 texels, 16,384 with transparent texels; beyond, the EWA estimate, reported: docs/rendering.md, Where exactness holds), point, bilinear (the base level), mip-point, mip-bilinear (the nearest MIP level), mip-point-linear, trilinear (the two nearest levels, mixed: XGL\'s six methods), ewa (elliptical weighted average, anisotropic). Sets both --min-filter and --mag-filter; a MIP filter or ewa magnifies with its base-level counterpart (point or bilinear). A record\'s "pattern" key "filter" overrides it (and these flags) for that record' -r -f -a "box\t'The exact area integral over texel cells'
point\t''
bilinear\t''
mip-point\t''
mip-bilinear\t''
mip-point-linear\t''
trilinear\t''
ewa\t''"
complete -c scene-render -l min-filter -d 'The filter where the pattern is minified (a pixel spans more than one texel after --lod-bias; XGL\'s filter1): overrides --filter. A record\'s "min_filter" overrides it' -r -f -a "box\t'The exact area integral over texel cells'
point\t''
bilinear\t''
mip-point\t''
mip-bilinear\t''
mip-point-linear\t''
trilinear\t''
ewa\t''"
complete -c scene-render -l mag-filter -d 'The filter where the pattern is magnified (XGL\'s filter2): box, point or bilinear (the MIP filters have nothing to do there, as in OpenGL). A record\'s "mag_filter" overrides it' -r -f -a "box\t'The exact area integral over texel cells'
point\t''
bilinear\t''
mip-point\t''
mip-bilinear\t''
mip-point-linear\t''
trilinear\t''
ewa\t''"
complete -c scene-render -l lod-bias -d 'Added to the MIP level of detail (log2 of texels per pixel), XGL\'s depth_interp_factor: 1.0 is one level blurrier, -1.0 one level sharper (and more aliased). A record\'s "pattern" key "lod_bias" overrides it' -r
complete -c scene-render -l mip-build -d 'The filter that builds MIP levels (in linear light, only when some pixel minifies under a MIP filter or ewa): mitchell (XGL\'s choice) or box' -r -f -a "box\t'The area average: each coarse texel is the mean of the fine texels it covers (exact area weights when the ratio is odd, 3 → 1)'
mitchell\t'The Mitchell-Netravali cubic (B = C = 1/3), as XGL\'s `xgl_mipmap_texture_build` ("XGL uses the Mitchell filter"): sharper than the box, with slight negative lobes (results are clamped to the valid range)'"
complete -c scene-render -l no-skip -d 'For benchmarks only: turn off the listed work-saving skips, a comma list of hidden (filter every opaque textured fragment, shown or not), mip (build MIP levels for every pattern up front), transparent (visit transparent texel runs in the box filter), magnify (cut fragments inside one texel cell). The output is the same; only the time differs (bench/skips.sh)' -r
complete -c scene-render -l stripe-lod -d 'Level of detail of stripe textures (docs/stripe.md): blended reads the two levels around the pixel\'s footprint (the gradient length of the texture coordinate) and blends them by the continuous fraction a; nearest reads the one nearest level' -r -f -a "nearest\t'The single level nearest to the pixel\'s footprint'
blended\t'A continuous level, blended linearly between the two nearest levels'"
complete -c scene-render -l cull -d 'Which faces to drop; the front is the side from which the vertices run counter-clockwise' -r -f -a "none\t'Draw both faces'
back\t'Drop polygons seen from behind (clockwise on screen)'
front\t'Drop polygons seen from the front (counter-clockwise on screen)'"
complete -c scene-render -l aa -d 'Anti-aliasing: none (pixel centres), ss<N> (N = k*k samples on a k x k grid, N up to 256), or exact (the exact visible area of every polygon in each pixel, box filter; a textured fragment meeting more than 65,536 texels, 16,384 with transparent texels, or a stripe fragment crossing more than 65,536 map-sample boundaries is estimated instead, and reported: docs/rendering.md, Where exactness holds)' -r
complete -c scene-render -l max-error -d 'Removed: kept only to say so to the scripts that pass it' -r
complete -c scene-render -l reference-samples -d 'Uniform strips per pixel added to the reference\'s events (a multiple of 3 from 3 to 3000; more only tightens the error estimate)' -r
complete -c scene-render -l compare -d 'Compare the image with this reference image and print RMSE, PSNR, the largest error and the share of pixels off by more than 4 (8-bit sRGB, over RGB). A 16-bit PNG, PPM or PAM, or a PFM, on either side is measured in fractional 8-bit codes and in linear light too' -r
complete -c scene-render -l image -d 'With --compare: measure this existing image instead of rendering a scene. The flags that shape a render or its output are refused with it' -r
complete -c scene-render -l diff -d 'With --compare: write the difference, amplified 16x per channel, here (an 8-bit PNG, PPM or PAM, whatever the inputs\' depth)' -r
complete -c scene-render -l frames -d 'Render an animation of N frames (docs/objects.md): numbers of instance transforms written `{"start": a, "step": s}` are `a + s*k` in frame k (0-based), and so are those of quadric records\' "transform". -o must then be a pattern such as frame-%04d.png, or a plain name with --animate' -r
complete -c scene-render -l fps -d 'With --animate: frames per second (each frame shows for 1/FPS s)' -r
complete -c scene-render -l quadric-tolerance -d 'Largest distance, in pixels, of a quadric\'s chords from its true surface, for quadric records that leave out slices or stacks (docs/objects.md): measured at the nearest point of the quadric\'s bounding sphere as drawn by this camera' -r
complete -c scene-render -l frame -d 'Render only frame K of the --frames (0-based): one job of a batch run by make -j, GNU parallel or a Slurm job array' -r
complete -c scene-render -l depfile -d 'Write the make rule of the output: every file the run read (the stream, its patterns and stripe files, the camera file, --background-pattern, --compare), as `cc -MD` does. Needs -o; with --frames, every frame is a target' -r
complete -c scene-render -l max-polygons -d 'The most polygons a frame may expand into (instances times their objects\' polygons, an empty object\'s counting one, quadrics their triangles): a scene over it is refused when read, before any work (a quadric without slices and stacks when the view has chosen them, before it is cut)' -r
complete -c scene-render -l threads -d 'Worker threads (default: all cores). The output is identical for any N' -r
complete -c scene-render -l no-perspective-correction -d 'Interpolate texture coordinates linearly on the screen instead of perspective-correctly (XGL\'s PERSP_NONE): faster hardware once, wrong under perspective; for reproducing such images'
complete -c scene-render -l cig-compat -d 'Stripe textures by the Compuscene III rule of seed 001 (Fig. 7): level = the binary exponent of the larger derivative ΔP_max, blend factor a in 4 bits, one table entry per level. Cheaper and coarser than blended'
complete -c scene-render -l reference -d 'Render the reference image instead (each pixel the average of the scene over its square in linear light, by an independent, slower method: exact along lines, exact between events along y); its own error estimate is reported on standard error, with the number of pixels whose 8-bit value it leaves uncertain (pixels meeting more than 1,024 texel lines or a plane\'s horizon, for one): it is no ground truth there (docs/rendering.md, Where exactness holds)'
complete -c scene-render -l json -d 'Print the --compare and --reference reports, and what --aa exact estimated, as one JSON object, {"version": 1, "tool": "scene-render", ...}; with --frames or --frame, one entry per frame in its "frames" array (docs/json.md). It goes to standard output, or standard error when the image does'
complete -c scene-render -l timings -d 'Print the time of each phase (read and project, render, write) to standard error'
complete -c scene-render -l animate -d 'With --frames: write one animated PNG (APNG) to -o, a plain name such as turn.png, instead of one file per frame. It loops forever; every frame is whole, and frame 0 is also the still image shown by viewers without APNG support'
complete -c scene-render -l no-progress -d 'Show no progress bar. Bars are drawn on standard error only when it is a terminal (and TERM is not "dumb"), never into a pipe or a file, and cleared when the job ends'
complete -c scene-render -s h -l help -d 'Print help (see more with \'--help\')'
complete -c scene-render -s V -l version -d 'Print version'
