int TestGridRayTraversal(int, char*[])
{
  return 1;
}
