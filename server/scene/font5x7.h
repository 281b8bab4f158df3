/*
 * font5x7.h - the built-in 5x7 pixel font used by the "text" shape (scene.h).
 *
 * Glyphs exist for printable ASCII 0x20..0x7E. Each is 5 pixel columns by 7 rows,
 * row 0 at the top; text lays glyphs out in 6-column cells (one blank spacing column).
 * Pure lookups on static data; thread-safe.
 */
#ifndef REFRACT_FONT5X7_H
#define REFRACT_FONT5X7_H

#include <stdbool.h>

#define FONT5X7_FIRST 0x20
#define FONT5X7_LAST 0x7e
#define FONT5X7_COLS 5
#define FONT5X7_ROWS 7
#define FONT5X7_CELL_COLS 6 /* glyph columns plus one spacing column */

/* Bit r (r = 0 is the top row) is set when that pixel of column col (0..4) of glyph ch
 * is lit. Returns 0 for the spacing column (col 5), other columns, or a character with
 * no glyph. */
unsigned scene_font5x7_column(int ch, int col);

/* True when pixel (col, row) of glyph ch is lit; row 0 is the top. */
bool scene_font5x7_lit(int ch, int col, int row);

#endif
