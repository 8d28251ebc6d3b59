/* main.c - the smoothfold command-line program (placeholder until the
 * commands land). */
#include <stdio.h>
int main(void) { puts("smoothfold"); return 0; }
