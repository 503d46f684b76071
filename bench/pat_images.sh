# The test images of bench/pat_from_image.sh and bench/pat_from_image_large.sh:
# name and ImageMagick source arguments (seeded where random). Sourced.
images=(
    "rose|rose:"
    "wizard|wizard:"
    "logo|logo:"
    "granite|granite:"
    "netscape|netscape:"
    "plasma|-seed 7 -size 256x256 plasma:fractal"
    "plasma2|-seed 3 -size 256x256 plasma:green-yellow"
    "gradient|-size 256x256 gradient:navy-gold"
    "radial|-size 256x256 radial-gradient:white-darkred"
    "drawing|-size 256x256 gradient:skyblue-white -fill tomato -draw 'circle 90,90 90,30' -fill seagreen -draw 'rectangle 140,120 240,230' -stroke black -strokewidth 5 -draw 'line 10,240 240,10' -fill gold -stroke none -draw 'ellipse 70,190 50,30 0,360'"
)
