/* The BML block the C embedding example sends; the test that checks the example
 * sends the same block through the C++ API and compares palettes. */
#ifndef C_EMBEDDING_BML_H
#define C_EMBEDDING_BML_H
#define C_EMBEDDING_BML                                                 \
  "<bml id='hello' characterId='robot'>"                                \
  "<head id='nod' lexeme='NOD' start='0' end='1.2'/>"                   \
  "<speech id='say' start='0.3'><text>Hello from C.</text></speech>"   \
  "</bml>"
#define C_EMBEDDING_FRAMES 180 /* 3 s at 60 Hz */
#endif
